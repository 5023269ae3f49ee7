"""A trust study's records (``trustcbr console export STUDY.db OUT``), as data and as tidy
frames: every event, the ratings beside the robot's inverse trust estimate, and each
participant's episode in the terms of a report's ``trials.jsonl``."""

from __future__ import annotations

import csv
import os
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Dict, List

from trustcbr._errors import TrustcbrError
from trustcbr._results import PathArg, _jsonl

if TYPE_CHECKING:
    import pandas

STUDY_FILES = ("events.jsonl", "ratings.csv", "episodes.jsonl")
"""The files of a study's export."""


@dataclass(repr=False)
class StudyResults:
    """A study's export (``trustcbr console export``): ``events``, every stored event in
    order per participant (``participant``, ``seq``, ``at_ms``, ``kind`` and the event's
    fields, docs/studies.md); ``ratings``, one row per trust rating with the robot's
    ``trust_estimate`` of the behavior just evaluated; ``episodes``, one record per
    participant in the fields of a report's ``trials.jsonl`` (``experiment`` is
    ``study/CONDITION``, ``operator`` the participant's pseudonym); ``out``, the folder."""

    events: List[Dict[str, Any]]
    ratings: List[Dict[str, Any]]
    episodes: List[Dict[str, Any]]
    out: str

    def __repr__(self) -> str:
        people = len(self.episodes)
        return (
            f"StudyResults({people} participants, {len(self.events)} events, "
            f"{len(self.ratings)} ratings; out={self.out!r})"
        )

    def events_frame(self) -> "pandas.DataFrame":
        """The events as a ``pandas.DataFrame``: one row per event, its fields as columns
        (absent fields are missing values)."""
        import pandas

        return pandas.DataFrame(self.events)

    def ratings_frame(self) -> "pandas.DataFrame":
        """The ratings as a ``pandas.DataFrame``: ``participant``, ``condition``,
        ``number``, ``after_command``, ``behaviors``, ``value``, ``scale_min``,
        ``scale_max``, ``trust_estimate``."""
        import pandas

        return pandas.DataFrame(self.ratings)

    def episodes_frame(self) -> "pandas.DataFrame":
        """The episodes as a ``pandas.DataFrame``: one row per participant, a column per
        field of ``trials.jsonl`` that is a number, a flag or a name, with ``condition``
        (the experiment's name without ``study/``) and ``given_up`` counted."""
        import pandas

        rows = []
        for e in self.episodes:
            row = {k: v for k, v in e.items() if not isinstance(v, (dict, list))}
            row["condition"] = str(e["experiment"]).removeprefix("study/")
            row["given_up"] = len(e.get("given_up", []))
            rows.append(row)
        return pandas.DataFrame(rows)


def _number(text: str) -> Any:
    try:
        value = float(text)
    except ValueError:
        return text
    return int(value) if value.is_integer() and "." not in text else value


def load_study(export_dir: PathArg) -> StudyResults:
    """The records of a trust study exported by ``trustcbr console export STUDY.db
    OUT``: pass ``OUT``."""
    root = os.fspath(export_dir)
    missing = [f for f in STUDY_FILES if not os.path.isfile(os.path.join(root, f))]
    if missing:
        raise TrustcbrError(
            f"{root}: not a study's export (no {', '.join(missing)}): write one with "
            "`trustcbr console export STUDY.db OUT`"
        )
    with open(os.path.join(root, "ratings.csv"), encoding="utf-8", newline="") as f:
        ratings = [
            {k: (v if k in ("participant", "condition") else _number(v)) for k, v in row.items()}
            for row in csv.DictReader(f)
        ]
    return StudyResults(
        events=_jsonl(os.path.join(root, "events.jsonl")),
        ratings=ratings,
        episodes=_jsonl(os.path.join(root, "episodes.jsonl")),
        out=root,
    )
