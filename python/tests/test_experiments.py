"""Experiments: suites from a dict, RON text, a file or the embedded one; records,
summary, pandas, the report folder, determinism, errors like the command line's."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

import trustcbr

from conftest import small_suite

REPO = Path(__file__).resolve().parents[2]


def test_a_dict_suite_gives_records_summary_and_table() -> None:
    results = trustcbr.run(small_suite())
    assert len(results.trials) == 2 * 12
    first = results.trials[0]
    assert first["experiment"] == "movement/balanced"
    assert first["arm"] == "random-walk"
    assert set(first["final"]) == {"speed", "padding"}
    experiment = results.summary["experiments"][0]
    assert experiment["name"] == "movement/balanced"
    assert set(results.arms()) == {"random-walk", "case-based"}
    assert "| movement | balanced | 12 |" in results.table
    assert results.config["trials"] == 12


def test_the_same_seed_gives_the_same_trials_on_any_thread_count() -> None:
    one = trustcbr.run(small_suite(), threads=1)
    two = trustcbr.run(small_suite(), threads=2)
    assert one.trials == two.trials
    other = trustcbr.run(small_suite(), seed=8)
    assert other.trials != one.trials


def test_to_pandas_holds_one_row_per_trial() -> None:
    pytest.importorskip("pandas")
    frame = trustcbr.run(small_suite()).to_pandas()
    assert len(frame) == 24
    means = frame.groupby("arm")["behaviors_evaluated"].mean()
    assert set(means.index) == {"random-walk", "case-based"}


def test_ron_text_and_a_file_run_as_the_dict_does(tmp_path: Path) -> None:
    text = """(seed: 7, trials: 12, arms: ["random-walk", "case-based"], landscape_runs: 0,
        limit: (runs: 0), experiments: [(scenario: "movement", operator: "balanced")])"""
    from_text = trustcbr.run(text=text)
    path = tmp_path / "suite.ron"
    path.write_text(text)
    from_file = trustcbr.run(path)
    assert from_text.trials == from_file.trials == trustcbr.run(small_suite()).trials


def test_the_report_folder_is_written_as_run_writes_it(tmp_path: Path) -> None:
    out = tmp_path / "report"
    results = trustcbr.run(small_suite(landscape_runs=2), out=out)
    for name in ["report.html", "table.md", "summary.json", "trials.jsonl", "config.ron"]:
        assert (out / name).is_file(), name
    lines = (out / "trials.jsonl").read_text().splitlines()
    assert [json.loads(line) for line in lines] == results.trials
    summary = json.loads((out / "summary.json").read_text())
    assert summary["experiments"] == results.summary["experiments"]


def test_errors_are_the_command_lines(tmp_path: Path) -> None:
    with pytest.raises(
        trustcbr.TrustcbrError, match=r"experiments\[0\].scenario: unknown scenario `moovement`"
    ):
        trustcbr.run(small_suite(experiments=[{"scenario": "moovement", "operator": "x"}]))
    with pytest.raises(
        trustcbr.TrustcbrError, match=r"arms\[0\]: unknown arm `nope` \(known: random-walk"
    ):
        trustcbr.run(small_suite(), arms=["nope"])
    with pytest.raises(trustcbr.TrustcbrError, match="trials"):
        trustcbr.run(small_suite(), trials=0)
    with pytest.raises(trustcbr.TrustcbrError, match="unknown field `colour`"):
        trustcbr.run(small_suite(colour="red"))


BIN = os.environ.get("TRUSTCBR_BIN") or shutil.which("trustcbr")


@pytest.mark.skipif(BIN is None, reason="set TRUSTCBR_BIN to the trustcbr binary")
def test_messages_match_the_binarys(tmp_path: Path) -> None:
    assert BIN is not None
    missing = str(tmp_path / "missing.ron")
    cases = [
        (lambda: trustcbr.run(missing), ["run", missing]),
        (lambda: trustcbr.run(arms=["nope"]), ["reproduce", "--arms", "nope"]),
        (
            lambda: trustcbr.Adapter("nowhere", str(tmp_path / "c.db")),
            ["serve", "--domain", "nowhere", "--cases", str(tmp_path / "c.db")],
        ),
    ]
    for call, args in cases:
        with pytest.raises(trustcbr.TrustcbrError) as raised:
            call()
        cli = subprocess.run([BIN, *args], capture_output=True, text=True, cwd=tmp_path)
        assert cli.returncode != 0
        assert cli.stderr.strip() == f"error: {raised.value}"


def test_the_embedded_suite_is_the_papers() -> None:
    text = trustcbr.default_suite()
    assert "experiments" in text
    assert trustcbr.builtin_arms()[:2] == ["random-walk", "case-based"]


@pytest.mark.skipif(BIN is None, reason="set TRUSTCBR_BIN to the trustcbr binary")
def test_the_report_is_the_binarys_byte_for_byte(tmp_path: Path) -> None:
    assert BIN is not None
    suite = tmp_path / "suite.ron"
    suite.write_text(
        """(seed: 3, trials: 10, arms: ["random-walk", "cause-aware"], landscape_runs: 0,
        limit: (runs: 0), experiments: [(scenario: "patrol", operator: "random")])"""
    )
    trustcbr.run(suite, out=tmp_path / "python")
    cli = subprocess.run(
        [BIN, "run", str(suite), "--out", str(tmp_path / "cli")], capture_output=True, text=True
    )
    assert cli.returncode == 0, cli.stderr
    for name in ["trials.jsonl", "table.md", "config.ron"]:
        assert (tmp_path / "python" / name).read_bytes() == (tmp_path / "cli" / name).read_bytes()
