"""What a run returns, and the same read back from a report folder: :class:`Results`
(an experiment suite) and :class:`MissionResults` (a mission suite), with tidy pandas
frames."""

from __future__ import annotations

import importlib
import json
import os
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Union

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


@dataclass(repr=False)
class Results:
    """What an experiment suite run returns (``trustcbr run``'s report, as data).

    ``trials``: one record per trial (``trials.jsonl``); ``summary``: ``summary.json``
    (every arm, paired tests, effect sizes, the known-operator limit); ``table``: every
    arm (``table.md``); ``paper_table``: the paper's two arms, as ``run`` prints it;
    ``config``: the config that ran; ``out``: the report folder, when one was written or
    read.
    """

    trials: List[Dict[str, Any]]
    summary: Dict[str, Any]
    table: str
    config: Dict[str, Any]
    paper_table: str = ""
    out: Optional[str] = field(default=None)

    def __repr__(self) -> str:
        names = [e["name"] for e in self.summary.get("experiments", [])]
        arms = list(self.config.get("arms", []))
        where = f", out={self.out!r}" if self.out else ""
        shown = ", ".join(names[:3]) + (f", ... ({len(names)} in all)" if len(names) > 3 else "")
        arm_list = ", ".join(arms)
        return f"Results({len(self.trials)} trials; experiments: {shown}; arms: {arm_list}{where})"

    def arms(self, experiment: Union[int, str] = 0) -> Dict[str, Dict[str, Any]]:
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
        strategies: Dict[str, Dict[str, Any]] = chosen["strategies"]
        return strategies

    def to_pandas(self) -> Any:
        """The trials as a tidy ``pandas.DataFrame``: one row per trial, flat columns
        (``final.speed``, ``initial.speed``, ``true_causes.deadline`` (0 when absent),
        ``given_up`` (how many behaviors were given up) and ``given_up_right`` (how many of
        their explanations were right)). The given-up behaviors themselves:
        :meth:`given_up_frame`."""
        pd = _pandas()
        causes = sorted({c for t in self.trials for c in t.get("true_causes", {})})
        rows = []
        for t in self.trials:
            row: Dict[str, Any] = {k: t.get(k) for k in TRIAL_COLUMNS}
            row["learned_start"] = bool(t.get("learned_start", False))
            _flat("final", t.get("final", {}), row)
            _flat("initial", t.get("initial", {}), row)
            for cause in causes:
                row[f"true_causes.{cause}"] = t.get("true_causes", {}).get(cause, 0)
            given_up = t.get("given_up", [])
            row["given_up"] = len(given_up)
            row["given_up_right"] = sum(1 for g in given_up if g.get("right"))
            rows.append(row)
        return pd.DataFrame.from_records(rows)

    def given_up_frame(self) -> Any:
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
        return pd.DataFrame.from_records(rows, columns=columns)

    def summary_frame(self) -> Any:
        """One row per experiment and arm: the summary's numbers, flat (``mean``,
        ``ci95``, ``commands_mean``, ..., ``explanations.first_reason_right``, ...)."""
        pd = _pandas()
        rows = []
        for e in self.summary["experiments"]:
            for arm, stats in e["strategies"].items():
                row: Dict[str, Any] = {"experiment": e["name"], "arm": arm}
                _flat("", stats, row)
                rows.append(row)
        return pd.DataFrame.from_records(rows)


@dataclass(repr=False)
class MissionResults:
    """What a mission suite run returns: ``missions``, one record per mission
    (``missions.jsonl``); ``summary`` (``summary.json``); ``table`` (``missions.md``);
    ``config``; ``out``."""

    missions: List[Dict[str, Any]]
    summary: Any
    table: str
    config: Dict[str, Any]
    out: Optional[str] = field(default=None)

    def __repr__(self) -> str:
        plans = [m.get("name") for m in self.config.get("missions", [])]
        where = f", out={self.out!r}" if self.out else ""
        return (
            f"MissionResults({len(self.missions)} missions; plans: {', '.join(map(str, plans))}; "
            f"arms: {', '.join(self.config.get('arms', []))}{where})"
        )

    def to_pandas(self) -> Any:
        """One row per mission, nested dicts flattened to dotted columns; lists (the
        changes, the alerts) are counted (``changes``, ``alerts``) rather than kept."""
        pd = _pandas()
        rows = []
        for m in self.missions:
            row: Dict[str, Any] = {}
            _flat("", m, row)
            for k, v in m.items():
                if isinstance(v, list):
                    row[k] = len(v)
            rows.append(row)
        return pd.DataFrame.from_records(rows)


def _jsonl(path: str) -> List[Dict[str, Any]]:
    with open(path, encoding="utf-8") as f:
        return [json.loads(line) for line in f if line.strip()]


def _read(path: str) -> str:
    with open(path, encoding="utf-8") as f:
        return f.read()


def load_report(report_dir: Union[str, "os.PathLike[str]"], read_config: Any) -> Any:
    """The results in a report folder that ``trustcbr run``/``reproduce`` or
    :func:`trustcbr.run` wrote."""
    from trustcbr._errors import TrustcbrError

    root = os.fspath(report_dir)
    config_path = os.path.join(root, "config.ron")
    if not os.path.isfile(config_path):
        raise TrustcbrError(f"{root}: not a report folder (it has no config.ron)")
    config = json.loads(read_config("file", "", config_path))
    summary = json.loads(_read(os.path.join(root, "summary.json")))
    if os.path.isfile(os.path.join(root, "missions.jsonl")):
        return MissionResults(
            missions=_jsonl(os.path.join(root, "missions.jsonl")),
            summary=summary,
            table=_read(os.path.join(root, "missions.md")),
            config=config,
            out=root,
        )
    return Results(
        trials=_jsonl(os.path.join(root, "trials.jsonl")),
        summary=summary,
        table=_read(os.path.join(root, "table.md")),
        config=config,
        paper_table="",
        out=root,
    )
