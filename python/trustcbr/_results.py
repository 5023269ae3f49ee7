"""What a run returns, and the same read back from a report folder: :class:`Results`
(an experiment suite) and :class:`MissionResults` (a mission suite), with tidy pandas
frames, and the shapes of their records and summaries."""

from __future__ import annotations

import importlib
import json
import os
import shutil
import sys
import tempfile
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, Dict, Iterable, List, Optional, Union

from trustcbr._errors import TrustcbrError
from trustcbr._types import Behavior

if sys.version_info >= (3, 11):  # pragma: no cover - depends on the interpreter
    from typing import NotRequired, TypedDict
else:  # pragma: no cover
    from typing_extensions import NotRequired, TypedDict

if TYPE_CHECKING:  # pragma: no cover - for the type checker only
    import pandas


class GivenUp(TypedDict):
    """A behavior a trial gave up: the ``reason`` its explanation settled on, the
    operator's most frequent true reason (``truth``, evaluation only) and whether the
    explanation was ``right``."""

    reason: Optional[str]
    truth: Optional[str]
    right: bool


class Trial(TypedDict):
    """One trial of an experiment (a line of ``trials.jsonl``).

    ``behaviors_evaluated``, ``commands`` and ``untrustworthy`` are what it cost;
    ``found_trustworthy`` whether it settled on a behavior its operator trusts; ``final``
    and ``initial`` the behaviors it ended and started with; ``searched`` and ``reused``
    how many behaviors the search and case reuse chose; ``retained`` whether it stored a
    case; ``truncated`` whether ``max_commands`` cut it off; ``true_causes`` the
    operator's true reasons for its untrustworthy commands (evaluation only); ``given_up``
    every behavior it gave up. Present only where they apply: ``learned_start``,
    ``goal_changes``, ``context``, ``told``, ``stated``, ``unheard``.
    """

    experiment: str
    scenario: str
    operator: str
    arm: str
    trial: int
    behaviors_evaluated: int
    commands: int
    untrustworthy: int
    found_trustworthy: bool
    final: Behavior
    initial: Behavior
    searched: int
    reused: int
    retained: bool
    truncated: bool
    true_causes: Dict[str, int]
    given_up: List[GivenUp]
    learned_start: NotRequired[bool]
    goal_changes: NotRequired[Dict[str, Any]]
    context: NotRequired[Dict[str, str]]
    told: NotRequired[Dict[str, str]]
    stated: NotRequired[List[Dict[str, Any]]]
    unheard: NotRequired[bool]


class ArmSummary(TypedDict):
    """One arm of one experiment in ``summary.json``: a row of
    :meth:`Results.summary_frame`, whose docstring says what each number is."""

    mean: float
    ci95: float
    commands_mean: float
    commands_ci95: float
    untrustworthy_mean: float
    untrustworthy_ci95: float
    found_share: float
    found_share_ci95: float
    cases_acquired: int
    reuses_cases: bool
    started_from_cases: int
    truncated: int
    t_test_p_vs_first: Optional[float]
    wilcoxon_p_vs_first: Optional[float]
    explanations: Dict[str, Any]
    behaviors_ratio_to_reference: Optional[Dict[str, float]]
    t_test_p_vs_reference: Optional[float]
    wilcoxon_p_vs_reference: Optional[float]
    ratio_to_limit: NotRequired[Dict[str, Optional[float]]]
    initial: NotRequired[str]
    ratio_to_free_first_limit: NotRequired[Dict[str, Optional[float]]]
    goal_changes: NotRequired[Dict[str, Any]]
    contexts: NotRequired[List[Dict[str, Any]]]


class ExperimentSummary(TypedDict):
    """One experiment in ``summary.json``: its arms' summaries (``strategies``, by arm
    name), the reference arm, the paired t-test's p between the first two arms
    (``p_value``) and the known-operator limit (``None`` when not estimated)."""

    name: str
    scenario: str
    operator: str
    trials: int
    arms: List[str]
    reference: str
    p_value: float
    strategies: Dict[str, ArmSummary]
    limit: Optional[Dict[str, Any]]


class Summary(TypedDict):
    """``summary.json``: every experiment, the run time, who ran it, and a benchmark
    suite's ``benchmark``."""

    provenance: Dict[str, Any]
    elapsed_s: float
    experiments: List[ExperimentSummary]
    benchmark: NotRequired[List[Dict[str, Any]]]


# Scalar fields of a trial record, in the order a frame shows them.
TRIAL_COLUMNS = (
    "experiment",
    "scenario",
    "operator",
    "arm",
    "trial",
    "behaviors_evaluated",
    "commands",
    "untrustworthy",
    "found_trustworthy",
    "searched",
    "reused",
    "retained",
    "truncated",
    "learned_start",
)


def _pandas() -> Any:
    try:
        return importlib.import_module("pandas")
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError("this needs pandas: pip install pandas") from e


def _flat(prefix: str, value: Any, row: Dict[str, Any]) -> None:
    """``value`` into ``row`` with dotted names: dicts flattened, lists left out."""
    if isinstance(value, dict):
        for k, v in value.items():
            _flat(f"{prefix}.{k}" if prefix else str(k), v, row)
    elif not isinstance(value, list):
        row[prefix] = value


def _frame(rows: List[Dict[str, Any]], first: Iterable[str] = ()) -> "pandas.DataFrame":
    """A frame of flattened rows, columns in the order first seen (``first`` before
    them). A field that is a dict in some rows and ``None`` in others (an arm's
    ``behaviors_ratio_to_reference``, ``None`` for the reference arm itself) is its
    dotted columns alone, left empty (NaN) in those rows, not a column of its own as
    well."""
    columns: Dict[str, None] = dict.fromkeys(first)
    for row in rows:
        columns.update(dict.fromkeys(row))
    nested = {name.rsplit(".", 1)[0] for name in columns if "." in name}
    nested |= {p for name in nested for p in _prefixes(name)}
    kept = [c for c in columns if c not in nested]
    frame: "pandas.DataFrame" = _pandas().DataFrame.from_records(
        [{k: v for k, v in row.items() if k not in nested} for row in rows], columns=kept
    )
    return frame


def _prefixes(name: str) -> List[str]:
    parts = name.split(".")
    return [".".join(parts[:i]) for i in range(1, len(parts))]


PathArg = Union[str, "os.PathLike[str]"]


@dataclass(repr=False)
class Results:
    """What an experiment suite run returns (``trustcbr run``'s report, as data).

    ``trials``: one record per trial (``trials.jsonl``); ``summary``: ``summary.json``
    (every arm, paired tests, effect sizes, the known-operator limit); ``table``: every
    arm (``table.md``); ``paper_table``: the paper's two arms, as ``run`` prints it, under
    a line saying what its numbers are (``±`` is the half-width of the 95% confidence
    interval); ``config``: the config that ran; ``out``: the report folder, when one was
    written or read. :meth:`save` writes the report folder.
    """

    trials: List[Trial]
    summary: Summary
    table: str
    config: Dict[str, Any]
    paper_table: str = ""
    out: Optional[str] = field(default=None)
    _report: Any = field(default=None, compare=False)

    def __repr__(self) -> str:
        names = [e["name"] for e in self.summary.get("experiments", [])]
        arms = list(self.config.get("arms", []))
        where = f", out={self.out!r}" if self.out else ""
        shown = ", ".join(names[:3]) + (f", ... ({len(names)} in all)" if len(names) > 3 else "")
        arm_list = ", ".join(arms)
        return f"Results({len(self.trials)} trials; experiments: {shown}; arms: {arm_list}{where})"

    def save(self, folder: PathArg) -> None:
        """Writes the report folder (``report.html``, ``table.md``, ``summary.json``,
        ``trials.jsonl``, ``config.ron``, the figures, copies of the operator files) that
        :func:`trustcbr.run` writes with ``out=folder``, byte for byte: the same results,
        run time and provenance. An earlier report in ``folder`` is replaced, as a run
        replaces it; any other non-empty folder is refused. Results read back with
        :func:`trustcbr.load` copy the folder they were read from. Sets :attr:`out`."""
        _save(self._report, self.out, folder, "trials.jsonl")
        self.out = os.fspath(folder)

    def arms(self, experiment: Union[int, str] = 0) -> Dict[str, ArmSummary]:
        """The summary of every arm of an experiment (by index or name), by arm name."""
        experiments = self.summary["experiments"]
        if isinstance(experiment, str):
            found = [e for e in experiments if e["name"] == experiment]
            if not found:
                known = ", ".join(e["name"] for e in experiments)
                raise KeyError(f"no experiment `{experiment}` (known: {known})")
            chosen = found[0]
        else:
            chosen = experiments[experiment]
        return chosen["strategies"]

    def to_pandas(self) -> "pandas.DataFrame":
        """The trials as a tidy ``pandas.DataFrame``: one row per trial, flat columns
        (the record's numbers and flags as :class:`Trial` names them, ``final.NAME`` and
        ``initial.NAME`` per component, ``true_causes.CAUSE`` per cause (0 when absent),
        ``given_up`` (how many behaviors were given up) and ``given_up_right`` (how many of
        their explanations were right)). The given-up behaviors themselves:
        :meth:`given_up_frame`."""
        causes = sorted({c for t in self.trials for c in t.get("true_causes", {})})
        rows = []
        for t in self.trials:
            record: Dict[str, Any] = dict(t)
            row: Dict[str, Any] = {k: record.get(k) for k in TRIAL_COLUMNS}
            row["learned_start"] = bool(t.get("learned_start", False))
            _flat("final", t.get("final", {}), row)
            _flat("initial", t.get("initial", {}), row)
            for cause in causes:
                row[f"true_causes.{cause}"] = t.get("true_causes", {}).get(cause, 0)
            given_up = t.get("given_up", [])
            row["given_up"] = len(given_up)
            row["given_up_right"] = sum(1 for g in given_up if g.get("right"))
            rows.append(row)
        return _frame(rows, TRIAL_COLUMNS)

    def given_up_frame(self) -> "pandas.DataFrame":
        """One row per behavior a trial gave up: ``experiment``, ``arm``, ``trial``,
        ``index`` (its place in the trial), the ``reason`` its explanation settled on, the
        operator's ``truth`` and whether the explanation was ``right``."""
        pd = _pandas()
        rows = [
            {
                "experiment": t["experiment"],
                "arm": t["arm"],
                "trial": t["trial"],
                "index": i,
                "reason": g.get("reason"),
                "truth": g.get("truth"),
                "right": bool(g.get("right")),
            }
            for t in self.trials
            for i, g in enumerate(t.get("given_up", []))
        ]
        columns = ["experiment", "arm", "trial", "index", "reason", "truth", "right"]
        frame: "pandas.DataFrame" = pd.DataFrame.from_records(rows, columns=columns)
        return frame

    def summary_frame(self) -> "pandas.DataFrame":
        """One row per experiment and arm, the summary's numbers flat (docs/python.md,
        *The summary frame's columns*, says what each is):

        - ``experiment``, ``arm``;
        - ``mean``, ``ci95``: behaviors evaluated per trial, its mean and the half-width
          of its 95% confidence interval; ``commands_mean``, ``commands_ci95`` and
          ``untrustworthy_mean``, ``untrustworthy_ci95`` likewise for commands and
          untrustworthy commands; ``found_share``, ``found_share_ci95``: the share of
          trials that settled on a behavior the operator trusts;
        - ``cases_acquired``, ``reuses_cases``, ``started_from_cases`` (cases it started
          with), ``truncated`` (trials cut off by ``max_commands``);
        - ``t_test_p_vs_first``, ``wilcoxon_p_vs_first``: paired tests against the first
          arm (NaN for the first); ``t_test_p_vs_reference``,
          ``wilcoxon_p_vs_reference``: against the reference arm (NaN for it);
        - ``behaviors_ratio_to_reference.ratio``, ``.ci95_low``, ``.ci95_high``: behaviors
          as a multiple of the reference arm's, with a 95% interval (NaN for it);
        - ``explanations.given_up``, ``explanations.first_reason_right`` and the same
          under ``explanations.perceivable.`` and ``explanations.other.``;
        - ``ratio_to_limit.behaviors``, ``.commands``, ``.untrustworthy``: the arm's mean
          as a multiple of the known-operator limit's (the paper's protocol; present when
          the suite estimates the limit, NaN where the limit is 0);
        - where they apply: ``initial`` and ``ratio_to_free_first_limit.*`` (an arm
          starting from the memory's guess), ``goal_changes.*`` (a suite with goal
          changes). Lists (``contexts``) are left out.
        """
        rows = []
        for e in self.summary["experiments"]:
            for arm, stats in e["strategies"].items():
                row: Dict[str, Any] = {"experiment": e["name"], "arm": arm}
                _flat("", stats, row)
                rows.append(row)
        return _frame(rows, ("experiment", "arm"))


@dataclass(repr=False)
class MissionResults:
    """What a mission suite run returns: ``missions``, one record per mission
    (``missions.jsonl``); ``summary`` (``summary.json``: one entry per plan); ``table``
    (``missions.md``); ``config``; ``out``; ``provenance`` (``provenance.json``: the
    tool, its version and commit, the command line; ``None`` for a report written before
    mission reports had one). :meth:`save` writes the report folder."""

    missions: List[Dict[str, Any]]
    summary: List[Dict[str, Any]]
    table: str
    config: Dict[str, Any]
    out: Optional[str] = field(default=None)
    provenance: Optional[Dict[str, Any]] = field(default=None)
    _report: Any = field(default=None, compare=False)

    def __repr__(self) -> str:
        plans = [m.get("name") for m in self.config.get("missions", [])]
        where = f", out={self.out!r}" if self.out else ""
        return (
            f"MissionResults({len(self.missions)} missions; plans: {', '.join(map(str, plans))}; "
            f"arms: {', '.join(self.config.get('arms', []))}{where})"
        )

    def save(self, folder: PathArg) -> None:
        """Writes the report folder :func:`trustcbr.run_missions` writes with
        ``out=folder``, byte for byte, as :meth:`Results.save` does. Sets :attr:`out`."""
        _save(self._report, self.out, folder, "missions.jsonl")
        self.out = os.fspath(folder)

    def to_pandas(self) -> "pandas.DataFrame":
        """One row per mission, nested dicts flattened to dotted columns; lists (the
        changes, the alerts) are counted (``changes``, ``alerts``) rather than kept."""
        rows = []
        for m in self.missions:
            row: Dict[str, Any] = {}
            _flat("", m, row)
            for k, v in m.items():
                if isinstance(v, list):
                    row[k] = len(v)
            rows.append(row)
        return _frame(rows)


def _save(report: Any, read_from: Optional[str], folder: PathArg, records: str) -> None:
    """Writes a report folder: from the run kept in ``report``, or a copy of the folder
    the results were read from."""
    target = os.fspath(folder)
    if report is not None:
        report.save(target)
        return
    if read_from is None or not os.path.isfile(os.path.join(read_from, records)):
        raise TrustcbrError(
            "save: these results hold no run to write (they were made by hand); "
            "run the suite with trustcbr.run, or read a report folder with trustcbr.load"
        )
    _copy_report(read_from, target)


def _copy_report(source: str, target: str) -> None:
    """Copies the report folder ``source`` to ``target``: written whole beside it first,
    then swapped in for an earlier report there; any other non-empty folder is refused."""
    if os.path.exists(target) and os.path.samefile(source, target):
        return
    if os.path.isdir(target) and os.listdir(target):
        if not os.path.isfile(os.path.join(target, "config.ron")):
            raise TrustcbrError(
                f"save: {target} is a folder holding files other than a report; "
                "give an empty or new folder, or one holding an earlier report"
            )
    elif os.path.exists(target) and not os.path.isdir(target):
        raise TrustcbrError(f"save: {target} is a file, not a folder")
    parent = os.path.dirname(os.path.abspath(target))
    os.makedirs(parent, exist_ok=True)
    staged = tempfile.mkdtemp(prefix=".report-", dir=parent)
    try:
        copy = os.path.join(staged, "report")
        shutil.copytree(source, copy)
        if os.path.isdir(target):
            aside = os.path.join(staged, "earlier")
            os.rename(target, aside)
        os.rename(copy, target)
    finally:
        shutil.rmtree(staged, ignore_errors=True)


def _jsonl(path: str) -> List[Any]:
    with open(path, encoding="utf-8") as f:
        return [json.loads(line) for line in f if line.strip()]


def _read(path: str) -> str:
    with open(path, encoding="utf-8") as f:
        return f.read()


def _report_folder(report_dir: PathArg) -> str:
    root = os.fspath(report_dir)
    if not os.path.isfile(os.path.join(root, "config.ron")):
        if os.path.isfile(os.path.join(root, "episodes.jsonl")):
            raise TrustcbrError(
                f"{root}: a trust study's export: read it with trustcbr.load_study(), "
                "which returns StudyResults"
            )
        raise TrustcbrError(f"{root}: not a report folder (it has no config.ron)")
    return root


def load_report(report_dir: PathArg, read_config: Callable[[str, str, str], str]) -> Results:
    """The results in an experiment suite's report folder that ``trustcbr
    run``/``reproduce`` or :func:`trustcbr.run` wrote."""
    root = _report_folder(report_dir)
    if os.path.isfile(os.path.join(root, "missions.jsonl")):
        raise TrustcbrError(
            f"{root}: a mission suite's report: read it with trustcbr.load_missions(), "
            "which returns MissionResults"
        )
    config = json.loads(read_config("file", "", os.path.join(root, "config.ron")))
    trials: List[Trial] = _jsonl(os.path.join(root, "trials.jsonl"))
    summary: Summary = json.loads(_read(os.path.join(root, "summary.json")))
    return Results(
        trials=trials,
        summary=summary,
        table=_read(os.path.join(root, "table.md")),
        config=config,
        paper_table="",
        out=root,
    )


def load_mission_report(
    report_dir: PathArg, read_config: Callable[[str, str, str], str]
) -> MissionResults:
    """The results in a mission suite's report folder that ``trustcbr run`` or
    :func:`trustcbr.run_missions` wrote."""
    root = _report_folder(report_dir)
    if not os.path.isfile(os.path.join(root, "missions.jsonl")):
        raise TrustcbrError(
            f"{root}: an experiment suite's report: read it with trustcbr.load(), "
            "which returns Results"
        )
    config = json.loads(read_config("file", "", os.path.join(root, "config.ron")))
    provenance = os.path.join(root, "provenance.json")
    return MissionResults(
        missions=_jsonl(os.path.join(root, "missions.jsonl")),
        summary=json.loads(_read(os.path.join(root, "summary.json"))),
        table=_read(os.path.join(root, "missions.md")),
        config=config,
        out=root,
        provenance=json.loads(_read(provenance)) if os.path.isfile(provenance) else None,
    )
