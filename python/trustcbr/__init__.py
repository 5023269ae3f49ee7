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
- :func:`explain` and :func:`load`: one trial of a report replayed, and a report folder
  (the command line's or Python's) read back as :class:`Results`;
- :mod:`trustcbr.gym`: Gymnasium environments (with the ``gym`` extra).

Every call that takes a ``catalog=`` serves another catalog's domains: a plug-in's own
extension module (``catalog_module!`` of the Rust crate ``trustcbr-python``), as
``examples/warehouse/python`` builds the warehouse's.

Behaviors are plain dicts of component name to value in real units, e.g.
``{"speed": 3.5, "padding": 0.4}``. Every error is a :class:`TrustcbrError` carrying the
message the command-line tool prints.
"""

from __future__ import annotations

import json
import math
import os
import secrets
import warnings
from dataclasses import dataclass
from types import ModuleType
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from trustcbr import _native
from trustcbr._errors import SearcherCheckError, TrustcbrError
from trustcbr._progress import Progress, ProgressCallback, ProgressOption, Reporter
from trustcbr._results import (
    ArmSummary,
    ExperimentSummary,
    MissionResults,
    Results,
    Summary,
    Trial,
    load_mission_report,
    load_report,
)
from trustcbr._study import StudyResults, load_study
from trustcbr._types import (
    Behavior,
    ContextSwitch,
    Decision,
    Evaluated,
    Outcome,
    Searcher,
    SearcherFactory,
    SimulatedOutcome,
    Space,
    Strategy,
)

__version__: str = _native.__version__

__all__ = [
    "RECOMMENDED_ARM",
    "Adapter",
    "ArmSummary",
    "Behavior",
    "ContextSwitch",
    "Decision",
    "Evaluated",
    "ExperimentSummary",
    "Explained",
    "Landscape",
    "MissionResults",
    "Outcome",
    "Progress",
    "ProgressCallback",
    "PythonArm",
    "Results",
    "Searcher",
    "SearcherCheckError",
    "SearcherFactory",
    "SimulatedOutcome",
    "Space",
    "Strategy",
    "StudyResults",
    "Suite",
    "Summary",
    "Trial",
    "TrustcbrError",
    "builtin_arms",
    "check_searcher",
    "default_suite",
    "explain",
    "landscape",
    "load",
    "load_missions",
    "load_study",
    "operators",
    "run",
    "run_missions",
    "scenarios",
    "simulate",
    "space",
    "strategies",
]

RECOMMENDED_ARM: str = _native.RECOMMENDED_ARM
"""The recommended arm (``case-based+nested``): the default of :class:`Adapter`'s ``arm``,
chosen on the benchmark's development instances (docs/search-strategies.md, *The
recommended arm*)."""

Catalog = Optional[ModuleType]
"""A catalog's extension module (``None``: the built-in UGV catalog, ``trustcbr._native``)."""


def _module(catalog: Catalog) -> Any:
    return _native if catalog is None else catalog


def _first_path(value: Any, bad: Callable[[Any], bool], path: str = "") -> Optional[str]:
    """The path of the first value inside ``value`` that is ``bad`` (``weight``,
    ``experiments[0].feedback.explains``), or ``None``."""
    if bad(value):
        return path or "value"
    if isinstance(value, Mapping):
        for k, v in value.items():
            found = _first_path(v, bad, f"{path}.{k}" if path else str(k))
            if found is not None:
                return found
    if isinstance(value, (list, tuple)):
        for i, v in enumerate(value):
            found = _first_path(v, bad, f"{path}[{i}]")
            if found is not None:
                return found
    return None


def _plain(value: Any) -> Any:
    """A value JSON has no form for, as the suite means it: a path as its text, a numpy
    number as the number."""
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    if isinstance(value, np.generic):
        return value.item()
    raise TypeError(type(value).__name__)


def _not_json(value: Any) -> bool:
    return not isinstance(
        value, (str, int, float, bool, type(None), Mapping, list, tuple, os.PathLike, np.generic)
    )


def _dumps(value: Mapping[str, Any]) -> str:
    """JSON text of a request or a suite (paths and numpy numbers as JSON writes them);
    JSON has no NaN or infinity, and no form for other objects, so they are refused
    naming where they are."""
    try:
        return json.dumps(value, allow_nan=False, default=_plain)
    except ValueError:
        found = _first_path(value, lambda v: isinstance(v, float) and not math.isfinite(v))
        raise TrustcbrError(f"field `{found}`: a finite number is required") from None
    except TypeError:
        found = _first_path(value, _not_json)
        if found is None:
            raise TrustcbrError("a dict's keys are field names (str)") from None
        kind = type(_at(value, found)).__name__
        raise TrustcbrError(
            f"field `{found}`: a {kind} has no form in a suite; give a str, a number, a bool, "
            "None, a list or a dict"
        ) from None


def _at(value: Any, path: Optional[str]) -> Any:
    """The value at ``path`` (as :func:`_first_path` writes it) inside ``value``."""
    if not path or path == "value":
        return value
    for part in path.replace("[", ".[").split("."):
        if part.startswith("["):
            value = value[int(part[1:-1])]
        elif part:
            value = value[part]
    return value


def _names(option: str, names: Optional[Sequence[str]]) -> Optional[List[str]]:
    """A list of names given as one; a str alone is refused (it is not a list of its
    letters)."""
    if names is None:
        return None
    if isinstance(names, str):
        raise TrustcbrError(f"{option}: a list of names, not a str (write {option}=[{names!r}])")
    return [str(n) for n in names]


@dataclass(frozen=True)
class PythonArm:
    """An arm whose search strategy is written in Python.

    ``factory(space)`` builds one searcher per chain of trials (an experiment's trials for
    this arm, in order), or one per trial when the trials are independent (no case reuse,
    ``learns_across_episodes`` false, no operator states a reason); see :class:`Searcher`
    for its methods. With ``reuses_cases`` the arm reuses cases first (Algorithm 1, the
    suite's retriever) and falls back on the searcher, as ``case-based+NAME`` arms do.
    """

    factory: SearcherFactory
    reuses_cases: bool = False


def _check_factory(label: str, factory: Any) -> None:
    """Refuses a factory that cannot be called, naming where it was given (``label``)."""
    if not callable(factory):
        raise TrustcbrError(
            f"{label}: a factory (a class or a function taking the space and returning a "
            f"searcher), got {type(factory).__name__} {factory!r}"
        )


def _python_arms(
    python_arms: Optional[Mapping[str, Union[PythonArm, SearcherFactory]]],
) -> List[Any]:
    if python_arms is None:
        return []
    if not isinstance(python_arms, Mapping):
        raise TrustcbrError("python_arms: a dict of arm name to factory (or PythonArm)")
    added = []
    for name, arm in python_arms.items():
        if not isinstance(name, str):
            raise TrustcbrError(f"python_arms: arm names are str, got {name!r}")
        if not isinstance(arm, PythonArm):
            arm = PythonArm(arm)
        _check_factory(f"python_arms[{name!r}]", arm.factory)
        added.append((name, arm.factory, arm.reuses_cases))
    return added


class Adapter:
    """The online trust adapter for one robot, ask/tell (``trustcbr serve`` in-process).

    ``domain`` is a scenario (``"movement"``, ``"patrol"``) or a RON domain file;
    ``cases`` is the case base: an SQLite file (created when absent), a ``postgres://`` URL,
    or a ``.ron`` file (read-only). ``seed`` drives the search and the behaviors the
    adapter draws. ``arm`` names the arm whose strategy is served: any built-in arm, by
    default the recommended one (``trustcbr.RECOMMENDED_ARM``), or ``"domain"`` for the
    domain file's own adapter config; ``strategy`` serves a strategy written in Python
    instead: the factory
    :func:`run` takes for ``python_arms`` (or a :class:`PythonArm`, to reuse cases first),
    so what is evaluated offline is deployed through the same API.
    With ``mission`` (``trustcbr serve --mission``) outcomes keep coming after an episode
    settles: the settled behavior is watched, a fall of its trust starts a new episode
    with a ``switch``, and an ``alert`` asks the operator to supervise. With ``competence``
    as well (``trustcbr serve --mission --competence``, a scenario's robot only) the robot
    judges its own competence, at most ``competence`` per command in every part, and an
    ``overtrust`` decision asks the operator to choose, once for a settled behavior it
    trusts while the robot is surely short of that. With ``detect_changes`` as well
    (``trustcbr serve --mission --detect-changes``) a settled behavior is also given up when
    a sequential test of its own record (a CUSUM) finds its rate of untrustworthy commands
    has risen (docs/missions.md, *A change detector*).
    Several adapters (processes, robots) may share one SQLite or PostgreSQL case base; an
    adapter belongs to the thread that made it (another thread's call raises
    :class:`TrustcbrError`).

    Every method sends one request of the protocol (docs/protocol.md) and returns its
    reply; a refused request raises :class:`TrustcbrError` and changes nothing.
    """

    def __init__(
        self,
        domain: str,
        cases: Union[str, "os.PathLike[str]"],
        *,
        seed: int = 0,
        arm: Optional[str] = None,
        strategy: Union[None, PythonArm, SearcherFactory] = None,
        mission: bool = False,
        competence: Optional[float] = None,
        detect_changes: bool = False,
        catalog: Catalog = None,
    ) -> None:
        served = None
        if strategy is not None:
            if not isinstance(strategy, PythonArm):
                strategy = PythonArm(strategy)
            _check_factory("strategy", strategy.factory)
            name = getattr(strategy.factory, "__name__", "python")
            served = (str(name), strategy.factory, strategy.reuses_cases)
        self._session = _module(catalog).session(
            str(domain),
            os.fspath(cases),
            seed,
            arm,
            served,
            mission,
            competence,
            bool(detect_changes),
        )

    def _request(self, request: Mapping[str, Any]) -> Dict[str, Any]:
        reply: Dict[str, Any] = json.loads(self._session.request(_dumps(request)))
        return reply

    @property
    def location(self) -> str:
        """Where the cases are kept."""
        return str(self._session.location)

    @property
    def writable(self) -> bool:
        """Whether retained cases are stored (a ``.ron`` case file is read-only)."""
        return bool(self._session.writable)

    def begin(
        self,
        behavior: Optional[Behavior] = None,
        *,
        context: Optional[Mapping[str, str]] = None,
        preferences: Optional[Mapping[str, bool]] = None,
    ) -> Behavior:
        """Starts an episode with ``behavior``, or one drawn uniformly at random; returns it.

        ``context`` sets the robot's context first (as :meth:`set_context` does), for
        example ``{"cargo": "hazardous"}``; without it the context stays as it was.
        ``preferences`` is what the new operator states up front, each of the domain's
        statement names (``config()["statements"]``; the UGV's ``hurry``, ``avoid-bumps``,
        ...) with whether it minds it, for example ``{"hurry": True}``: the search may take
        it as a prior. A name the domain does not declare raises ``TrustcbrError``.
        """
        request: Dict[str, Any] = {"request": "begin"}
        if behavior is not None:
            request["behavior"] = dict(behavior)
        if context is not None:
            request["context"] = dict(context)
        if preferences is not None:
            request["preferences"] = {name: bool(minds) for name, minds in preferences.items()}
        started: Behavior = self._request(request)["behavior"]
        return started

    def set_context(self, context: Mapping[str, str]) -> Dict[str, str]:
        """Sets the robot's context from now on, between episodes: each variable the domain
        declares (the UGV's ``cargo``, ``normal`` or ``hazardous``, and ``situation``,
        ``routine`` or ``emergency``) with its value; the rest are at their defaults.
        Episodes begun afterwards are matched with the cases learned in that context and
        retain it in their case. Returns the context, its defaults left out."""
        reply = self._request({"request": "context", "context": dict(context)})
        current: Dict[str, str] = reply["context"]
        return current

    def switch_context(self, context: Mapping[str, str]) -> ContextSwitch:
        """In mission mode, once a behavior is in use: tells the robot its context switched
        (docs/missions.md, "Context switches"). An episode under way ends, what the robot
        learned of how its operator reacts is forgotten, and it goes back to the behavior it
        last settled on, trusted, in the new context since its operator began (unless it
        gave it up there since), or else carries on with the behavior in use. Raises
        ``TrustcbrError``, changing nothing, outside mission mode or before the first
        ``begin`` (use ``set_context`` there)."""
        state = self.state()
        if "watching" not in state or (state["episode"] is None and state["watching"] is None):
            raise TrustcbrError(
                "switch_context tells a robot on a mission (mission=True) of a switch once "
                "a behavior is in use; between episodes, set_context sets the context"
            )
        reply = self._request({"request": "context", "context": dict(context)})
        return ContextSwitch(
            behavior=reply["behavior"],
            origin=str(reply["from"]),
            gave_up_watch=bool(reply["gave_up_watch"]),
            context=dict(reply["context"]),
        )

    @property
    def context(self) -> Dict[str, str]:
        """The robot's context: the variables set away from their defaults (empty: the
        default context)."""
        current: Dict[str, str] = self.state().get("context", {})
        return current

    def tell(
        self,
        outcome: str,
        *,
        weight: float = 1.0,
        duration_s: float = 0.0,
        observed: Sequence[str] = (),
        stated: Optional[str] = None,
        confidence: Optional[float] = None,
        goal_change: bool = False,
    ) -> Decision:
        """Reports how the last command ended and returns what to do next.

        ``outcome`` is ``"completed"``, ``"failed"`` or ``"interrupted"``; ``observed`` lists
        what the robot perceived itself (observations the domain declares); ``stated`` is
        the reason the operator gave, if any (a cause the domain declares); ``confidence``
        is the robot's own confidence in ``[0, 1]`` that the command went as it should, when
        it assesses itself. ``goal_change=True`` says instead of a reason that the operator
        stopped the robot because its goals changed (an ``"interrupted"`` outcome only): the
        command counts against nothing, and the behavior is kept. The decision is ``keep``,
        ``switch`` (use ``behavior`` from now on), ``settled`` (the episode is over), with the
        explanation of a switch or an end,
        or in mission mode ``alert`` (keep the behavior and ask the operator to supervise)
        and, with ``competence``, ``overtrust`` (keep it and ask the operator to choose).
        Call :meth:`begin` first.
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
        if goal_change:
            request["goal_change"] = True
        return Decision(self._tell(request))

    def _tell(self, request: Mapping[str, Any]) -> Dict[str, Any]:
        try:
            return self._request(request)
        except TrustcbrError as e:
            if "no episode is under way" in str(e):
                raise TrustcbrError(
                    "no episode is under way: call begin() first (and again after an "
                    "episode settles, unless the adapter is in mission mode)"
                ) from None
            raise

    def tell_outcome(self, outcome: Mapping[str, Any]) -> Decision:
        """Reports an outcome given as a dict, such as :func:`simulate` returns (its
        ``truth`` is left out: a robot is never told it; and the ``seed`` it was drawn
        from)."""
        request = {k: v for k, v in outcome.items() if k not in ("truth", "seed")}
        return Decision(self._tell(request))

    def accept_offer(self) -> Behavior:
        """Takes the safer behavior the last ``overtrust`` decision offered
        (:attr:`Decision.offer`), right after it: the robot watches it from now on, at the
        trustworthy threshold. Raises ``TrustcbrError`` when no offer stands."""
        accepted: Behavior = self._request({"request": "accept_offer"})["behavior"]
        return accepted

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


def scenarios(*, catalog: Catalog = None) -> List[str]:
    """The catalog's scenarios (built in: ``movement``, ``patrol``)."""
    return list(_module(catalog).scenarios())


def operators(scenario: str, *, catalog: Catalog = None) -> List[str]:
    """The built-in operators of ``scenario``."""
    return list(_module(catalog).operators(scenario))


def space(scenario: str, *, catalog: Catalog = None) -> Space:
    """The behavior space of a scenario: components (name, unit, values in real units),
    the number of behaviors, the declared causes and observations."""
    described: Dict[str, Any] = _module(catalog).space(scenario)
    return Space(
        components=described["components"],
        behaviors=int(described["behaviors"]),
        causes=[c["name"] for c in described["causes"]],
        observations=list(described["observations"]),
    )


def simulate(
    scenario: str,
    behavior: Behavior,
    operator: str,
    seed: Optional[int] = None,
    *,
    catalog: Catalog = None,
) -> SimulatedOutcome:
    """Runs one command of a scenario with ``behavior`` in front of ``operator`` (a
    built-in name or an operator file), every random draw from ``seed``: the same seed
    gives the same command. Without ``seed`` a fresh one is drawn for each call (from the
    operating system), so calls in a loop meet the operator afresh each time; the seed
    used is returned, to run the command again.

    Returns the outcome as the adapter is told it (``outcome``, ``weight``, ``duration_s``,
    ``observed``: what the robot perceived, ``stated``: the reason the operator gave, if
    any, and ``confidence`` when the robot assesses itself), ``truth``, the operator's
    true reason, for evaluation only, and ``seed``, the seed it was drawn from.
    :meth:`Adapter.tell_outcome` takes it as it is.
    """
    if seed is None:
        seed = secrets.randbits(64)
    elif isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**64:
        raise TrustcbrError(f"seed: a whole number from 0 to 2**64 - 1, got {seed!r}")
    result: SimulatedOutcome = _module(catalog).simulate(scenario, dict(behavior), operator, seed)
    result["seed"] = seed
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


def landscape(
    scenario: str,
    operator: str,
    runs: int = 100,
    seed: int = 0,
    *,
    progress: ProgressOption = True,
    catalog: Catalog = None,
) -> Landscape:
    """Estimates every behavior's completion rate under ``operator`` from ``runs`` commands
    each (``trustcbr landscape``'s estimate and its limit: 1 to 10,000 runs), on every
    core, showing progress (see :func:`run`); Ctrl-C stops it."""
    if isinstance(runs, bool) or not isinstance(runs, int) or runs < 0:
        raise TrustcbrError(f"runs: a number of runs from 1 to 10000, got {runs!r}")
    reporter = Reporter(progress, f"landscape of {operator}", "behavior")
    try:
        shares, lengths, names = _module(catalog).landscape(
            scenario, operator, runs, seed, reporter.native()
        )
    finally:
        reporter.close()
    values = [c["values"] for c in space(scenario, catalog=catalog)["components"]]
    array = np.asarray(shares, dtype=np.float64).reshape(tuple(lengths))
    return Landscape(p_complete=array, components=list(names), values=values, runs=runs)


def default_suite(*, catalog: Catalog = None) -> str:
    """The embedded suite (the paper's seven experiments) as RON, as ``trustcbr config``."""
    return str(_module(catalog).default_suite())


def builtin_arms(*, catalog: Catalog = None) -> List[str]:
    """The built-in arms and the catalog's own, in report order: each registered strategy
    alone, then after case reuse where it is offered so (:func:`strategies`), then the
    catalog's."""
    return list(_module(catalog).builtin_arms())


def strategies() -> List[Strategy]:
    """The search strategies' registry, the paper's random walk first: every built-in
    strategy with what it does and the arms it is offered as (the same list the command
    line, the reports and :func:`builtin_arms` read)."""
    rows: List[Strategy] = _native.strategies()
    return rows


Suite = Union[None, str, "os.PathLike[str]", Mapping[str, Any]]
"""A suite: a RON file's path, a dict with the file's fields, or ``None`` for the embedded
one."""

PathArg = Union[str, "os.PathLike[str]"]
"""A path, as a str or a :class:`pathlib.Path`."""


def _suite_form(suite: Suite, text: Optional[str]) -> Tuple[str, str, str]:
    if text is not None:
        if suite is not None:
            raise TrustcbrError("give a suite or its text, not both")
        if not isinstance(text, str):
            raise TrustcbrError(f"text: RON text (a str), got {type(text).__name__}")
        return "ron", text, "<text>"
    if suite is None:
        return "embedded", "", ""
    if isinstance(suite, Mapping):
        return "json", _dumps(suite), "<dict>"
    if isinstance(suite, (str, os.PathLike)):
        return "file", "", os.fspath(suite)
    raise TrustcbrError(f"suite: a RON file's path, a dict or None, got {type(suite).__name__}")


def _base(base: Optional[PathArg], kind: str) -> Optional[str]:
    """The folder a suite given as text or a dict reads its files from (``None``: the
    working directory); refused beside a file, whose own folder is its base."""
    if base is None:
        return None
    if kind == "file":
        raise TrustcbrError(
            "base: a suite file's operator files are read relative to the file itself; "
            "base= is for a suite given as text= or a dict"
        )
    if kind == "embedded":
        raise TrustcbrError("base: the embedded suite reads no files; base= is for text= or a dict")
    folder = os.fspath(base)
    if not os.path.isdir(folder):
        raise TrustcbrError(f"base: no folder {folder}")
    return os.path.abspath(folder)


def _path(value: Optional[PathArg]) -> Optional[str]:
    return None if value is None else os.fspath(value)


def _run(
    expect: str,
    suite: Suite,
    text: Optional[str],
    base: Optional[PathArg],
    out: Optional[PathArg],
    options: Dict[str, Any],
    python_arms: Optional[Mapping[str, Union[PythonArm, SearcherFactory]]],
    progress: ProgressOption,
    catalog: Catalog,
) -> Dict[str, Any]:
    """Runs a suite through the native runner, refusing one of the other kind (``expect``
    is ``experiments`` or ``missions``) with the function that runs it."""
    kind, body, origin = _suite_form(suite, text)
    request: Dict[str, Any] = {
        "kind": kind,
        "text": body,
        "origin": origin,
        "base": _base(base, kind),
        "expect": expect,
        "out": _path(out),
        "trials": None,
        "count": None,
        "commands": None,
        "seed": None,
        "landscape_runs": None,
        "arms": None,
        "threads": None,
        "save_cases": None,
        "cases": None,
    }
    request.update(options)
    request["arms"] = _names("arms", request["arms"])
    request["python_arms"] = _python_arms(python_arms)
    for option in ("trials", "count", "commands", "seed", "landscape_runs", "threads"):
        _count(option, request[option])
    unit = "trial" if expect == "experiments" else "mission"
    reporter = Reporter(progress, "run", unit)
    request["progress"] = reporter.native()
    try:
        ran: Dict[str, Any] = _module(catalog).run_suite(request)
    finally:
        reporter.close()
    return ran


def _count(option: str, value: Any) -> None:
    """Refuses a count that is not an int (a bool, a float, a str) naming the option; its
    range is the command line's, checked natively."""
    if value is None:
        return
    if isinstance(value, bool) or not isinstance(value, int):
        raise TrustcbrError(f"{option}: a whole number, got {value!r}")
    if value < 0:
        raise TrustcbrError(f"{option}: must not be negative, got {value}")


def run(
    suite: Suite = None,
    *,
    text: Optional[str] = None,
    base: Optional[PathArg] = None,
    out: Optional[PathArg] = None,
    trials: Optional[int] = None,
    seed: Optional[int] = None,
    arms: Optional[Sequence[str]] = None,
    landscape_runs: Optional[int] = None,
    threads: Optional[int] = None,
    python_arms: Optional[Mapping[str, Union[PythonArm, SearcherFactory]]] = None,
    save_cases: Optional[PathArg] = None,
    cases: Optional[PathArg] = None,
    progress: ProgressOption = True,
    catalog: Catalog = None,
) -> Results:
    """Runs an experiment suite as ``trustcbr run`` does and returns its :class:`Results`
    (a mission suite, one with a ``missions`` field, is :func:`run_missions`'s).

    ``suite`` is a RON file's path, a dict with the file's fields, or ``None`` for the
    embedded suite; ``text`` gives RON text instead. A file's operator files are read
    relative to the file; those of text or a dict relative to ``base`` (a folder), by
    default the working directory, and one missing there is refused saying where it was
    looked for. ``trials``, ``seed``, ``arms``, ``landscape_runs``, ``threads``,
    ``save_cases`` and ``cases`` are ``run``'s options, with its limits.
    ``python_arms`` maps arm names to :class:`PythonArm` (or a bare factory); name them in
    ``arms`` (or the suite's) to run them, paired trial by trial with the built-in arms;
    a name of a built-in arm, or one not run, is refused. With Python arms the run is
    single-threaded (Python runs one thread at a time). ``out`` writes the report folder
    (``report.html``, ``table.md``, ``summary.json``, ``trials.jsonl``, ...) as ``trustcbr
    run --out`` does; :meth:`Results.save` writes the same folder after the run.

    ``progress``: ``True`` shows a bar on stderr when it is a terminal, ``False`` shows
    nothing, a callable is called with a :class:`Progress` about ten times a second.
    Ctrl-C stops the run within a second (a Python arm included) and writes nothing.
    """
    options = {
        "trials": trials,
        "seed": seed,
        "arms": arms,
        "landscape_runs": landscape_runs,
        "threads": threads,
        "save_cases": _path(save_cases),
        "cases": _path(cases),
    }
    ran = _run("experiments", suite, text, base, out, options, python_arms, progress, catalog)
    return Results(
        trials=[json.loads(line) for line in ran["records"].splitlines() if line],
        summary=json.loads(ran["summary"]),
        table=ran["table"],
        paper_table=ran["paper_table"],
        config=json.loads(ran["config"]),
        out=_path(out),
        _report=ran["report"],
    )


def run_missions(
    suite: Suite,
    *,
    text: Optional[str] = None,
    base: Optional[PathArg] = None,
    out: Optional[PathArg] = None,
    count: Optional[int] = None,
    commands: Optional[int] = None,
    seed: Optional[int] = None,
    arms: Optional[Sequence[str]] = None,
    threads: Optional[int] = None,
    python_arms: Optional[Mapping[str, Union[PythonArm, SearcherFactory]]] = None,
    progress: ProgressOption = True,
    catalog: Catalog = None,
) -> MissionResults:
    """Runs a mission suite (one with a ``missions`` field, docs/missions.md) as ``trustcbr
    run`` does and returns its :class:`MissionResults`.

    ``suite``, ``text``, ``base``, ``out``, ``seed``, ``arms``, ``threads``,
    ``python_arms`` and ``progress`` are as :func:`run` takes them. ``count`` and
    ``commands`` set every plan's missions per arm and commands per mission, to shrink a
    suite (or grow it) without editing it: 1 to the most a suite may hold (1,000,000
    missions, 100,000,000 commands), the suite's own totals checked as it runs. The
    options of experiments (trials, landscapes, case bases) are not taken.
    """
    if suite is None and text is None:
        raise TrustcbrError(
            "suite: a mission suite's file, dict or text (there is no embedded one)"
        )
    options = {
        "count": count,
        "commands": commands,
        "seed": seed,
        "arms": arms,
        "threads": threads,
    }
    ran = _run("missions", suite, text, base, out, options, python_arms, progress, catalog)
    return MissionResults(
        missions=[json.loads(line) for line in ran["records"].splitlines() if line],
        summary=json.loads(ran["summary"]),
        table=ran["table"],
        config=json.loads(ran["config"]),
        out=_path(out),
        provenance=json.loads(ran["provenance"]),
        _report=ran["report"],
    )


def load(report_dir: PathArg, *, catalog: Catalog = None) -> Results:
    """The results in an experiment suite's report folder, written by ``trustcbr
    run``/``reproduce`` or by :func:`run` with ``out`` (or :meth:`Results.save`), as
    :class:`Results` (its ``paper_table`` is empty: the folder's ``table.md`` is
    :attr:`Results.table`, every arm). A mission suite's folder is
    :func:`load_missions`'s."""
    return load_report(report_dir, _module(catalog).read_config)


def load_missions(report_dir: PathArg, *, catalog: Catalog = None) -> MissionResults:
    """The results in a mission suite's report folder, written by ``trustcbr run`` or by
    :func:`run_missions` with ``out`` (or :meth:`MissionResults.save`)."""
    return load_mission_report(report_dir, _module(catalog).read_config)


@dataclass(frozen=True)
class Explained:
    """One trial told (``trustcbr explain``): ``story``, the text the command line
    prints, and ``record``, the trial's record as in ``trials.jsonl``'s terms."""

    story: str
    record: Dict[str, Any]

    def __str__(self) -> str:
        return self.story


def explain(
    report: Union[str, "os.PathLike[str]"],
    *,
    experiment: str,
    arm: str,
    trial: int,
    cases: Union[None, str, "os.PathLike[str]"] = None,
    python_arms: Optional[Mapping[str, Union[PythonArm, SearcherFactory]]] = None,
    catalog: Catalog = None,
) -> Explained:
    """Replays one trial of a report folder as ``trustcbr explain REPORT --experiment E
    --arm A --trial N [--cases DIR]`` does: every behavior, its commands, the trust
    estimate after each and the explanation of every switch. A report with Python arms is
    read too: its built-in arms are replayed, and a Python arm when its factory is given
    in ``python_arms`` (otherwise the error says which arms can be replayed). A report
    whose config, case bases or tool version differ from what ran is refused; one that
    records nothing to check them by (an earlier version's) is replayed with a
    ``UserWarning`` saying so."""
    story, record, replay_warnings = _module(catalog).explain(
        os.fspath(report),
        experiment,
        arm,
        trial,
        None if cases is None else os.fspath(cases),
        _python_arms(python_arms),
    )
    for warning in replay_warnings:
        warnings.warn(warning, UserWarning, stacklevel=2)
    return Explained(story=story, record=json.loads(record))


def _distinct(behaviors: Sequence[Mapping[str, Any]]) -> int:
    return len({tuple(sorted(b.items())) for b in behaviors})


def _searcher_failure(failure: Mapping[str, Any]) -> Tuple[str, str]:
    """What went wrong in a broken rule's case, and the change that fixes that case, in a
    Python strategy's terms."""
    rule = str(failure["rule"])
    space = failure["space"]
    size = int(space["behaviors"])
    evaluated = [e["behavior"] for e in failure["evaluated"]]
    untried = size - _distinct(evaluated)
    proposal = failure["proposal"]
    returned = None if proposal is None else proposal["returned"]
    if rule == "in-space":
        return (
            f"propose() returned {returned!r}, which is not a behavior of the space",
            "return a dict with every component of the space (space['components']) "
            "and one of its values",
        )
    if rule == "untried" and untried == 0:
        return (
            "propose() returned a behavior already evaluated when every behavior of the "
            "space was evaluated",
            "return None once every behavior of the space is in `evaluated` (the one that "
            "resisted longest is kept)",
        )
    if rule == "untried":
        return (
            f"propose() returned {returned!r}, which was already evaluated, while "
            f"{untried} of {size} behaviors were untried",
            "return a behavior not in `evaluated` while any is untried",
        )
    if rule == "exhausted-only-when-all-tried" and not evaluated:
        return (
            "propose() returned None with nothing evaluated yet",
            "return a behavior of the space while any is untried (here, its one behavior)",
        )
    if rule == "exhausted-only-when-all-tried":
        return (
            f"propose() returned None while {untried} of {size} behaviors were untried",
            "return one of the untried behaviors; return None only once every behavior of "
            "the space is in `evaluated`",
        )
    if rule in ("keeps-an-evaluated", "one-proposal-per-behavior"):
        return (
            str(failure["message"]),
            "return None once every behavior of the space is in `evaluated`, and never "
            "a behavior already in it",
        )
    if rule == "rationale":
        return (
            str(failure["message"]),
            "return from rationale() one plain line (not empty, no newline) of at most "
            '160 bytes, or {"expects": ..., "confidence": p} with p in [0, 1] or None',
        )
    if rule == "deterministic":
        return (
            "two fresh searchers proposed differently for the same seed and evidence",
            "draw every random number from the `rng` given to propose(), not from the "
            "module `random`, numpy's global state or the clock",
        )
    if rule == "forgets-unless-it-learns":
        return (
            "a searcher proposed differently after an earlier episode than a fresh one, "
            "though it does not say it learns",
            "set `learns_across_episodes = True` on the searcher: it carries something "
            "from one episode to the next",
        )
    return str(failure["message"]), "see docs/python.md, *The conformance kit*"


def check_searcher(
    factory: SearcherFactory, *, scenario: Optional[str] = None, catalog: Catalog = None
) -> None:
    """Runs the searcher conformance kit over searchers built by ``factory(space)``, on
    random small spaces (components named ``c0``, ``c1``, ...) or, with ``scenario``, on
    that scenario's own space (for a strategy written for its components): proposals in
    the space, never an evaluated behavior while one is untried, ``None`` only when every
    behavior was tried, the same proposals for the same seed, one-line rationales, and no
    change after an episode unless ``learns_across_episodes``.

    Raises :class:`SearcherCheckError` with the rule broken, the failing case in Python
    terms and the change that fixes that case (a searcher that repeats a behavior once
    every one was tried is told to return ``None``; one that repeats while some are
    untried, to return an untried one), or the searcher's own exception.
    """
    _check_factory("factory", factory)
    failure = _module(catalog).check_searcher(factory, scenario)
    if failure is None:
        return
    rule = failure["rule"]
    proposal = failure["proposal"]
    evaluated = [e["behavior"] for e in failure["evaluated"]]
    what, fix = _searcher_failure(failure)
    case = (
        f"on a space of {failure['space']['behaviors']} behaviors "
        f"({', '.join(c['name'] for c in failure['space']['components'])}), "
        f"after evaluating {evaluated!r}"
    )
    message = f"the searcher breaks the rule `{rule}`: {what}; {case}. To fix it: {fix}."
    raise SearcherCheckError(
        message,
        rule=rule,
        space=failure["space"],
        evaluated=failure["evaluated"],
        proposal=proposal,
        seed=failure["seed"],
    )
