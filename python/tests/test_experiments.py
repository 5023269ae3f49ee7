"""Experiments: suites from a dict, RON text, a file or the embedded one; records,
summary, pandas, the report folder, determinism, errors like the command line's."""

from __future__ import annotations

import json
import os
import shutil
import signal
import subprocess
import threading
from pathlib import Path
from typing import Any, Iterator, List

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


def test_a_str_of_arms_is_refused_as_not_a_list() -> None:
    with pytest.raises(
        trustcbr.TrustcbrError,
        match=r"arms: a list of names, not a str \(write arms=\['uniform'\]\)",
    ):
        trustcbr.run(small_suite(), arms="uniform")


def test_a_nan_nested_in_a_dict_is_named_by_its_path() -> None:
    suite = small_suite(
        experiments=[
            {"scenario": "movement", "operator": "balanced", "feedback": {"explains": float("nan")}}
        ]
    )
    with pytest.raises(
        trustcbr.TrustcbrError, match=r"field `experiments\[0\]\.feedback\.explains`: a finite"
    ):
        trustcbr.run(suite)


def test_the_command_lines_limits_apply() -> None:
    with pytest.raises(trustcbr.TrustcbrError, match="threads: must be 1 to 256, got 100000"):
        trustcbr.run(small_suite(), threads=100000)
    with pytest.raises(trustcbr.TrustcbrError, match="threads: must be 1 to 256, got 0"):
        trustcbr.run(small_suite(), threads=0)
    with pytest.raises(trustcbr.TrustcbrError, match="runs: must be 1 to 10000, got 4294967295"):
        trustcbr.landscape("movement", "balanced", runs=4294967295)
    with pytest.raises(trustcbr.TrustcbrError, match="landscape_runs: must be 0 to 10000"):
        trustcbr.run(small_suite(), landscape_runs=10001)


def test_results_have_a_short_repr_every_arm_and_tidy_frames() -> None:
    pytest.importorskip("pandas")
    results = trustcbr.run(small_suite(arms=["random-walk", "case-based", "uniform"]))
    assert repr(results) == (
        "Results(36 trials; experiments: movement/balanced; arms: random-walk, case-based, uniform)"
    )
    # The full table names every arm; the paper's names its two.
    assert "uniform" in results.table and "uniform" not in results.paper_table
    frame = results.to_pandas()
    assert len(frame) == 36
    for column in ["final.speed", "initial.padding", "given_up", "given_up_right"]:
        assert column in frame.columns
    assert not any(frame[c].map(lambda v: isinstance(v, (dict, list))).any() for c in frame)
    given_up = results.given_up_frame()
    assert list(given_up.columns) == [
        "experiment",
        "arm",
        "trial",
        "index",
        "reason",
        "truth",
        "right",
    ]
    assert len(given_up) == int(frame["given_up"].sum())
    summary = results.summary_frame()
    assert list(summary["arm"]) == ["random-walk", "case-based", "uniform"]
    assert "explanations.first_reason_right" in summary.columns


def test_a_report_folder_loads_back(tmp_path: Path) -> None:
    out = tmp_path / "report"
    results = trustcbr.run(small_suite(), out=out)
    loaded = trustcbr.load(out)
    assert loaded.trials == results.trials
    assert loaded.summary["experiments"] == results.summary["experiments"]
    assert loaded.table == results.table
    assert loaded.config == results.config
    with pytest.raises(trustcbr.TrustcbrError, match="not a report folder"):
        trustcbr.load(tmp_path)


@pytest.mark.skipif(BIN is None, reason="set TRUSTCBR_BIN to the trustcbr binary")
def test_a_report_folder_the_command_line_wrote_loads(tmp_path: Path) -> None:
    assert BIN is not None
    suite = tmp_path / "suite.ron"
    suite.write_text(
        """(seed: 3, trials: 10, arms: ["random-walk", "cause-aware"], landscape_runs: 0,
        limit: (runs: 0), experiments: [(scenario: "patrol", operator: "random")])"""
    )
    cli = subprocess.run(
        [BIN, "run", str(suite), "--out", str(tmp_path / "cli")], capture_output=True, text=True
    )
    assert cli.returncode == 0, cli.stderr
    loaded = trustcbr.load(tmp_path / "cli")
    assert loaded.trials == trustcbr.run(suite).trials
    assert loaded.config["arms"] == ["random-walk", "cause-aware"]


def test_a_mission_suite_runs_and_loads(tmp_path: Path) -> None:
    suite = {
        "seed": 1,
        "arms": ["case-based"],
        "missions": [
            {
                "name": "short",
                "operators": {"scenario": "movement", "operator": "random"},
                "count": 3,
                "commands": 200,
                "changes": {"every": 100.0, "takeover": 0.5},
            }
        ],
    }
    out = tmp_path / "missions"
    results = trustcbr.run_missions(suite, out=out)
    assert isinstance(results, trustcbr.MissionResults)
    assert len(results.missions) == 3
    assert repr(results).startswith("MissionResults(3 missions; plans: short; arms: case-based")
    loaded = trustcbr.load_missions(out)
    assert loaded.missions == results.missions
    # What wrote the report, as the run said and as its folder keeps it.
    assert results.provenance is not None
    assert results.provenance["tool"] == "trustcbr"
    assert results.provenance["command_line"] == ["python", "trustcbr.run"]
    assert loaded.provenance == results.provenance
    # Each kind of suite has its function, typed by what it returns.
    with pytest.raises(
        trustcbr.TrustcbrError, match=r"a mission suite .*trustcbr.run_missions\(\)"
    ):
        trustcbr.run(suite)
    with pytest.raises(trustcbr.TrustcbrError, match=r"an experiment suite .*trustcbr.run\(\)"):
        trustcbr.run_missions(small_suite())
    with pytest.raises(trustcbr.TrustcbrError, match=r"trustcbr.load_missions\(\)"):
        trustcbr.load(out)
    trustcbr.run(small_suite(), out=tmp_path / "experiments")
    with pytest.raises(trustcbr.TrustcbrError, match=r"trustcbr.load\(\)"):
        trustcbr.load_missions(tmp_path / "experiments")


def test_progress_reaches_a_callback_and_can_be_silenced(capfd: Any) -> None:
    seen: List[trustcbr.Progress] = []
    trustcbr.run(small_suite(), progress=seen.append)
    assert seen[0].done == 0 and seen[-1].done == seen[-1].total == 24
    assert all(p.unit == "trial" for p in seen)
    assert [p.done for p in seen] == sorted(p.done for p in seen)
    trustcbr.run(small_suite(), progress=False)
    # Not on a terminal (pytest captures stderr), the default draws no bar either.
    trustcbr.run(small_suite())
    assert capfd.readouterr().err == ""
    with pytest.raises(TypeError, match="progress"):
        trustcbr.run(small_suite(), progress="yes")  # type: ignore[arg-type]


@pytest.fixture
def ctrl_c_reaches_python() -> Iterator[None]:
    """Python's own Ctrl-C handler while the test runs: a process started with SIGINT
    ignored (a background job of a shell without job control, as some CI runners start
    their steps) has none, and a signal it ignores would stop nothing."""
    before = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, before)


def interrupt_soon() -> threading.Timer:
    """Ctrl-C, as a terminal sends it, half a second from now."""
    timer = threading.Timer(0.5, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    return timer


@pytest.mark.usefixtures("ctrl_c_reaches_python")
def test_ctrl_c_stops_a_long_run_and_writes_nothing(tmp_path: Path) -> None:
    out = tmp_path / "report"
    interrupt_soon()
    # Without the stop this run takes many minutes.
    with pytest.raises(KeyboardInterrupt):
        trustcbr.run(trials=30000, arms=["random-walk"], out=out, save_cases=tmp_path / "cases")
    assert not out.exists() and not (tmp_path / "cases").exists()


@pytest.mark.usefixtures("ctrl_c_reaches_python")
def test_ctrl_c_stops_a_landscape() -> None:
    interrupt_soon()
    with pytest.raises(KeyboardInterrupt):
        trustcbr.landscape("patrol", "detection-focused", runs=10000)


def test_errors_speak_of_the_call_not_the_command_line(tmp_path: Path) -> None:
    # A bad field of a dict is named by its path in the dict, not a line and column of
    # JSON text the user never wrote.
    with pytest.raises(trustcbr.TrustcbrError) as raised:
        trustcbr.run(small_suite(trials="many"))
    assert (
        str(raised.value) == '<dict>: trials: invalid type: string "many", expected a nonzero u32'
    )
    nested = small_suite(
        experiments=[
            {"scenario": "movement", "operator": "balanced", "feedback": {"explains": "x"}}
        ]
    )
    with pytest.raises(trustcbr.TrustcbrError) as raised:
        trustcbr.run(nested)
    assert str(raised.value).startswith("<dict>: experiments[0].feedback.explains: invalid type")
    assert "line" not in str(raised.value) and "column" not in str(raised.value)
    plan = {"name": "p", "operators": {"scenario": "movement", "operator": "random"}}
    missions = {"seed": 1, "arms": ["case-based"], "missions": [dict(plan, count=-3)]}
    with pytest.raises(trustcbr.TrustcbrError, match=r"^<dict>: missions\[0\].count: invalid"):
        trustcbr.run_missions(missions)
    # Paths and numpy numbers are taken as the values they stand for; other objects are
    # refused by their place.
    import numpy as np

    ran = trustcbr.run(small_suite(trials=np.int64(3), seed=np.uint64(7)))
    assert len(ran.trials) == 2 * 3
    with pytest.raises(trustcbr.TrustcbrError, match=r"field `experiments\[0\].operator`: a set"):
        trustcbr.run(small_suite(experiments=[{"scenario": "movement", "operator": {"a"}}]))
    # Options are named as the call names them.
    with pytest.raises(trustcbr.TrustcbrError, match=r"^cases: no folder .*nowhere"):
        trustcbr.run(small_suite(), cases=tmp_path / "nowhere")
    with pytest.raises(trustcbr.TrustcbrError, match=r"^trials: a whole number, got '5'"):
        trustcbr.run(small_suite(), trials="5")  # type: ignore[arg-type]
