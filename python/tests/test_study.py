"""A trust study's export read by ``trustcbr.load_study``: the console run as a real
process, participants served over its HTTP API, the export written by the binary."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import urllib.request
from pathlib import Path
from typing import Any, Dict, Iterator, Optional

import pytest

import trustcbr

BIN = os.environ.get("TRUSTCBR_BIN") or shutil.which("trustcbr")
ROOT = Path(__file__).resolve().parents[2]
PILOT = ROOT / "domains" / "studies" / "pilot.ron"


def _call(url: str, body: Optional[Dict[str, Any]] = None, token: Optional[str] = None) -> Any:
    data = None if body is None else json.dumps(body).encode()
    request = urllib.request.Request(url, data=data, method="GET" if body is None else "POST")
    request.add_header("Content-Type", "application/json")
    if token is not None:
        request.add_header("Authorization", f"Bearer {token}")
    with urllib.request.urlopen(request, timeout=30) as reply:
        return json.loads(reply.read() or b"null")


@pytest.fixture
def console(tmp_path: Path) -> Iterator[str]:
    assert BIN is not None
    process = subprocess.Popen(
        [BIN, "console", "--study", str(PILOT), "--db", str(tmp_path / "pilot.db")]
        + ["--listen", "127.0.0.1:0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    try:
        assert process.stdout is not None
        line = process.stdout.readline().strip()
        assert line.startswith("listening on "), line
        yield line.removeprefix("listening on ")
    finally:
        process.kill()
        process.wait()


@pytest.mark.skipif(BIN is None, reason="set TRUSTCBR_BIN to the trustcbr binary")
def test_a_study_export_loads_into_tidy_frames(console: str, tmp_path: Path) -> None:
    for _ in range(2):
        token = _call(f"{console}/api/participants", {"consent": True})["token"]
        state = _call(f"{console}/api/shown", {"command": 0}, token)
        half = state["command"]["run"]["duration_s"] / 2
        state = _call(f"{console}/api/stop", {"command": 0, "at_s": half}, token)
        if state["phase"] == "state-cause":
            state = _call(f"{console}/api/statement", {"command": 0, "cause": "deadline"}, token)
        assert state["last"]["outcome"] == "interrupted"
    out = tmp_path / "export"
    subprocess.run(
        [str(BIN), "console", "export", str(tmp_path / "pilot.db"), str(out)], check=True
    )
    study = trustcbr.load_study(out)
    assert repr(study).startswith("StudyResults(2 participants, ")
    episodes = study.episodes_frame()
    assert sorted(episodes["condition"]) == ["explained", "silent"]
    assert list(episodes["commands"]) == [1, 1]
    assert list(episodes["untrustworthy"]) == [1, 1]
    events = study.events_frame()
    assert list(events[events["participant"] == "P001"]["kind"]) == [
        "enrolled",
        "shown",
        "stop",
        "statement",
        "decision",
    ]
    assert study.ratings_frame().empty, "no rating is asked before a behavior ends"
    with pytest.raises(trustcbr.TrustcbrError, match="load_study"):
        trustcbr.load(out)


def test_a_folder_that_is_no_export_is_refused(tmp_path: Path) -> None:
    with pytest.raises(trustcbr.TrustcbrError, match="not a study's export"):
        trustcbr.load_study(tmp_path)
