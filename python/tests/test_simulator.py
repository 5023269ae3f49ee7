"""The simulator: one command, determinism for a seed, operators by name or file,
landscapes as numpy arrays, and errors."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import trustcbr

REPO = Path(__file__).resolve().parents[2]


def test_scenarios_operators_and_spaces() -> None:
    assert trustcbr.scenarios() == ["movement", "patrol"]
    assert "balanced" in trustcbr.operators("movement")
    space = trustcbr.space("movement")
    assert [c["name"] for c in space["components"]] == ["speed", "padding"]
    assert space["behaviors"] == 20 * 20
    assert space["components"][0]["values"][:3] == [0.5, 1.0, 1.5]
    assert "collision" in space.get("observations", [])
    with pytest.raises(
        trustcbr.TrustcbrError, match=r"unknown scenario `lab` \(known: movement, patrol\)"
    ):
        trustcbr.operators("lab")


def test_one_command_is_the_same_for_the_same_seed() -> None:
    behavior = {c["name"]: c["values"][1] for c in trustcbr.space("patrol")["components"]}
    outcomes = [
        trustcbr.simulate("patrol", behavior, "detection-focused", seed=s) for s in range(30)
    ]
    again = [trustcbr.simulate("patrol", behavior, "detection-focused", seed=s) for s in range(30)]
    assert outcomes == again
    kinds = {o["outcome"] for o in outcomes}
    assert kinds <= {"completed", "failed", "interrupted"}
    declared = set(trustcbr.space("patrol").get("observations", []))
    for o in outcomes:
        assert set(o["observed"]) <= declared
        assert o["duration_s"] >= 0.0
        assert (o["truth"] is None) == (o["outcome"] == "completed")


def test_an_operator_file_is_read(tmp_path: Path) -> None:
    files = sorted((REPO / "domains" / "operators" / "movement").glob("*.ron"))
    assert files
    outcome = trustcbr.simulate("movement", {"speed": 1.0, "padding": 0.5}, str(files[0]), seed=1)
    assert outcome["outcome"] in {"completed", "failed", "interrupted"}


def test_bad_behaviors_and_operators_are_refused() -> None:
    with pytest.raises(trustcbr.TrustcbrError, match="speed"):
        trustcbr.simulate("movement", {"speed": 100.0, "padding": 0.2}, "balanced")
    with pytest.raises(trustcbr.TrustcbrError, match="padding"):
        trustcbr.simulate("movement", {"speed": 1.0}, "balanced")
    with pytest.raises(
        trustcbr.TrustcbrError,
        match=r"`nobody` is neither an operator of movement \(speed-focused, safety-focused, "
        r"balanced\) nor an operator file",
    ):
        trustcbr.simulate("movement", {"speed": 1.0, "padding": 0.2}, "nobody")


def test_landscapes_are_arrays_over_the_components() -> None:
    landscape = trustcbr.landscape("movement", "balanced", runs=10, seed=2)
    assert isinstance(landscape.p_complete, np.ndarray)
    assert landscape.p_complete.shape == (20, 20)
    assert ((landscape.p_complete >= 0.0) & (landscape.p_complete <= 1.0)).all()
    assert landscape.components == ["speed", "padding"]
    best = np.unravel_index(np.argmax(landscape.p_complete), landscape.p_complete.shape)
    assert set(landscape.behavior(tuple(int(i) for i in best))) == {"speed", "padding"}
    again = trustcbr.landscape("movement", "balanced", runs=10, seed=2)
    assert np.array_equal(landscape.p_complete, again.p_complete)


def test_without_a_seed_each_call_draws_one_and_returns_it() -> None:
    behavior = {"speed": 9.5, "padding": 0.2}
    outcomes = [trustcbr.simulate("movement", behavior, "balanced") for _ in range(20)]
    # Repeated calls meet the operator afresh: as many seeds and runs as calls.
    assert len({o["seed"] for o in outcomes}) == 20
    assert len({o["duration_s"] for o in outcomes}) > 1
    # The seed returned runs the same command again; a pinned seed always does.
    first = outcomes[0]
    assert trustcbr.simulate("movement", behavior, "balanced", seed=first["seed"]) == first
    pinned = [trustcbr.simulate("movement", behavior, "balanced", seed=5) for _ in range(3)]
    assert pinned[0] == pinned[1] == pinned[2] and pinned[0]["seed"] == 5
    with pytest.raises(trustcbr.TrustcbrError, match="seed: a whole number from 0 to 2"):
        trustcbr.simulate("movement", behavior, "balanced", seed=-1)
