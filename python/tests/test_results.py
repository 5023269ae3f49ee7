"""What a researcher does with results: shrink a mission suite, read a suite's files from
a folder of its own, save a report after the run, read the summary frame and the paper's
table, and have mypy --strict check code that uses them."""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Any, Dict

import pytest

import trustcbr

from conftest import small_suite

REPO = Path(__file__).resolve().parents[2]


def mission_suite(**plan: Any) -> Dict[str, Any]:
    """One movement plan, as a user writes it before shrinking it."""
    spec: Dict[str, Any] = {
        "name": "short",
        "operators": {"scenario": "movement", "operator": "random"},
        "count": 50,
        "commands": 400,
        "changes": {"every": 100.0, "takeover": 0.5},
    }
    spec.update(plan)
    return {"seed": 1, "arms": ["case-based"], "missions": [spec]}


def tree(folder: Path) -> Dict[str, bytes]:
    """Every file under ``folder`` by its path in it, with its bytes."""
    return {
        str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()
    }


def test_a_mission_suite_shrinks_from_python(tmp_path: Path) -> None:
    shrunk = trustcbr.run_missions(mission_suite(), count=2, commands=150)
    assert len(shrunk.missions) == 2
    assert [(p["count"], p["commands"]) for p in shrunk.config["missions"]] == [(2, 150)]
    # The same missions as the suite written that small.
    written = trustcbr.run_missions(mission_suite(count=2, commands=150))
    assert shrunk.missions == written.missions
    # The limits of a suite's own fields.
    with pytest.raises(trustcbr.TrustcbrError, match="count: must be 1 to 1000000, got 0"):
        trustcbr.run_missions(mission_suite(), count=0)
    with pytest.raises(trustcbr.TrustcbrError, match="commands: must be 1 to 100000000"):
        trustcbr.run_missions(mission_suite(), commands=10**9)
    with pytest.raises(trustcbr.TrustcbrError, match="count: a whole number, got 2.5"):
        trustcbr.run_missions(mission_suite(), count=2.5)  # type: ignore[arg-type]


def operator_file(folder: Path) -> Path:
    """An operator file of one's own, in ``folder``: the balanced operator, renamed."""
    source = REPO / "domains" / "operators" / "movement" / "balanced.ron"
    target = folder / "mine.ron"
    target.write_text(source.read_text().replace('name: "balanced"', 'name: "mine"'))
    return target


def test_a_suite_given_as_text_reads_its_files_from_base(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    folder = tmp_path / "suite"
    folder.mkdir()
    operator_file(folder)
    text = """(seed: 7, trials: 4, arms: ["random-walk"], landscape_runs: 0, limit: (runs: 0),
        experiments: [(scenario: "movement", operator_files: ["mine.ron"])])"""
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    # Looked for in the working directory, and said so.
    with pytest.raises(trustcbr.TrustcbrError) as missing:
        trustcbr.run(text=text)
    message = str(missing.value)
    assert message.startswith("experiments[0].operator_files[0]: no operator file `mine.ron`")
    assert f"in the working directory ({elsewhere}), as no base= was given" in message
    from_base = trustcbr.run(text=text, base=folder)
    assert len(from_base.trials) == 4
    # A dict too, and a mission suite.
    suite = small_suite(
        trials=4,
        arms=["random-walk"],
        experiments=[{"scenario": "movement", "operator_files": ["mine.ron"]}],
    )
    assert trustcbr.run(suite, base=folder).trials == from_base.trials
    with pytest.raises(trustcbr.TrustcbrError, match=r"no operator file `mine.ron` in base="):
        trustcbr.run(suite, base=elsewhere)
    plan = {"scenario": "movement", "operator": "random", "operator_files": ["mine.ron"]}
    with pytest.raises(
        trustcbr.TrustcbrError, match=r"missions\[0\].operators.operator_files\[0\]: no operator"
    ):
        trustcbr.run_missions(mission_suite(operators=plan), count=1)
    missions = trustcbr.run_missions(mission_suite(operators=plan), count=1, base=folder)
    assert len(missions.missions) == 1
    # The working directory is the default base.
    monkeypatch.chdir(folder)
    assert trustcbr.run(text=text).trials == from_base.trials
    with pytest.raises(trustcbr.TrustcbrError, match="base: a suite file's operator files"):
        trustcbr.run(tmp_path / "suite.ron", base=folder)


def test_save_writes_the_folder_out_writes(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    folder = tmp_path / "suite"
    folder.mkdir()
    operator_file(folder)
    suite = small_suite(
        landscape_runs=2,
        limit={"runs": 5},
        experiments=[
            {"scenario": "movement", "operator": "balanced"},
            {"scenario": "movement", "operator_files": ["mine.ron"]},
        ],
    )
    written = trustcbr.run(suite, base=folder, out=tmp_path / "out")
    monkeypatch.chdir(tmp_path)  # the operator file is read again from where it was
    written.save(tmp_path / "saved")
    assert tree(tmp_path / "saved") == tree(tmp_path / "out")
    assert "operators/mine.ron" in tree(tmp_path / "saved")
    assert written.out == str(tmp_path / "saved")
    # Saved again over it: an earlier report is replaced, as a run replaces it.
    written.save(tmp_path / "saved")
    assert tree(tmp_path / "saved") == tree(tmp_path / "out")
    # Results read back copy their folder.
    trustcbr.load(tmp_path / "out").save(tmp_path / "copied")
    assert tree(tmp_path / "copied") == tree(tmp_path / "out")
    # A run without out=, saved later: the same report but for its own run time.
    later = trustcbr.run(suite, base=folder)
    later.save(tmp_path / "later")
    saved, out = tree(tmp_path / "later"), tree(tmp_path / "out")
    assert saved.keys() == out.keys()
    differ = sorted(name for name in saved if saved[name] != out[name])
    assert set(differ) <= {"summary.json", "report.html"}
    summaries = [json.loads(t["summary.json"]) for t in (saved, out)]
    for summary in summaries:
        summary.pop("elapsed_s")
    assert summaries[0] == summaries[1]
    # Where a report cannot go.
    (tmp_path / "notes").mkdir()
    (tmp_path / "notes" / "todo.txt").write_text("mine")
    with pytest.raises(trustcbr.TrustcbrError, match="todo.txt"):
        later.save(tmp_path / "notes")
    with pytest.raises(trustcbr.TrustcbrError, match="hold no run"):
        trustcbr.Results(trials=[], summary=later.summary, table="", config={}).save(tmp_path / "x")


def test_mission_results_save_as_out_writes(tmp_path: Path) -> None:
    ran = trustcbr.run_missions(mission_suite(), count=2, commands=150, out=tmp_path / "out")
    ran.save(tmp_path / "saved")
    assert tree(tmp_path / "saved") == tree(tmp_path / "out")
    trustcbr.load_missions(tmp_path / "out").save(tmp_path / "copied")
    assert tree(tmp_path / "copied") == tree(tmp_path / "out")


def documented_columns() -> str:
    """docs/python.md's table of the summary frame's columns."""
    page = (REPO / "docs" / "python.md").read_text(encoding="utf-8")
    section = page.split("### The summary frame's columns", 1)[1]
    return section.split("\n#", 1)[0]


def test_the_summary_frame_has_no_spurious_column_and_every_column_is_documented() -> None:
    pytest.importorskip("pandas")
    results = trustcbr.run(small_suite(limit={"runs": 5}, arms=["random-walk", "case-based"]))
    frame = results.summary_frame()
    columns = list(frame.columns)
    # A field that is a dict for some arms is its dotted columns alone.
    assert "behaviors_ratio_to_reference" not in columns
    assert "behaviors_ratio_to_reference.ratio" in columns
    assert not [c for c in columns if any(d.startswith(c + ".") for d in columns)]
    assert frame.set_index("arm").loc["case-based", "behaviors_ratio_to_reference.ratio"] != 1.0
    assert {"ratio_to_limit.behaviors", "ratio_to_limit.untrustworthy"} <= set(columns)
    table = documented_columns()
    named = set(re.findall(r"`([a-z0-9_.*]+)`", table))
    for column in columns:
        assert column in named or any(
            n.endswith(".*") and column.startswith(n[:-1]) for n in named
        ), f"{column} is not in docs/python.md's table of the summary frame's columns"


def test_the_paper_table_says_what_plus_minus_is() -> None:
    table = trustcbr.run(small_suite()).paper_table
    heading, rest = table.split("\n\n", 1)
    assert "mean ± the half-width of its 95% confidence interval" in heading.replace("\n", " ")
    assert rest.startswith("| Scenario | Operator | Trials |")


USER_CODE = """\
from typing import List

import trustcbr

experiment = {{"scenario": "movement", "operator": "random"}}
suite = {{"seed": 1, "trials": 5, "experiments": [experiment]}}
results = trustcbr.run(suite, arms=["random-walk", "case-based"])
frame = results.summary_frame()
means = frame.groupby("arm")["mean"].mean()
evaluated: int = results.trials[0]["{field}"]
reference: str = results.summary["experiments"][0]["reference"]
paper: str = results.paper_table
{results_call}
missions = trustcbr.run_missions("missions.ron", count=2, commands=100)
plans: List[str] = [m["plan"] for m in missions.missions]
missions.to_pandas().groupby("arm").size()
trustcbr.load("report").save("copy")
trustcbr.load_missions("missions-report").save("missions-copy")
outcome = trustcbr.simulate("movement", {{"speed": 1.0, "padding": 0.2}}, "balanced")
seed: int = outcome["seed"]
"""


def test_mypy_strict_checks_code_using_the_results(tmp_path: Path) -> None:
    pytest.importorskip("mypy")
    good = tmp_path / "good.py"
    good.write_text(
        USER_CODE.format(field="behaviors_evaluated", results_call="results.save('report')")
    )
    bad = tmp_path / "bad.py"
    bad.write_text(
        USER_CODE.format(field="behaviours_evaluated", results_call="results.summary_fram()")
    )
    checked = subprocess.run(
        [sys.executable, "-m", "mypy", "--strict", "--no-error-summary", "good.py", "bad.py"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        env={**os.environ, "MYPY_CACHE_DIR": str(tmp_path / ".mypy_cache")},
    )
    errors = checked.stdout.splitlines()
    assert not [e for e in errors if e.startswith("good.py")], checked.stdout + checked.stderr
    assert any('"Results" has no attribute "summary_fram"' in e for e in errors), checked.stdout
    assert any('"Trial" has no key "behaviours_evaluated"' in e for e in errors), checked.stdout
    assert all(e.startswith("bad.py") for e in errors), checked.stdout
