"""A plug-in's catalog from Python: the warehouse's own extension module
(examples/warehouse/python, one line of Rust) served by the same Python API."""

from __future__ import annotations

from pathlib import Path

import pytest

import trustcbr

warehouse = pytest.importorskip(
    "warehouse_trustcbr", reason="pip install ./examples/warehouse/python (.ci/test-all does)"
)


def test_the_warehouses_scenario_operators_and_space() -> None:
    assert trustcbr.scenarios(catalog=warehouse) == ["picking"]
    assert "balanced" in trustcbr.operators("picking", catalog=warehouse)
    space = trustcbr.space("picking", catalog=warehouse)
    assert space["behaviors"] == 1800
    assert [c["name"] for c in space["components"]][:2] == ["gripper", "map"]


def test_a_suite_runs_over_the_warehouse_with_a_python_arm(tmp_path: Path) -> None:
    from conftest import UniformSearcher

    suite = {
        "seed": 3,
        "trials": 8,
        "arms": ["random-walk", "py-uniform"],
        "landscape_runs": 0,
        "limit": {"runs": 0},
        "experiments": [{"scenario": "picking", "operator": "balanced"}],
    }
    results = trustcbr.run(
        suite, python_arms={"py-uniform": UniformSearcher}, catalog=warehouse, out=tmp_path / "r"
    )
    assert {t["arm"] for t in results.trials} == {"random-walk", "py-uniform"}
    assert trustcbr.load(tmp_path / "r", catalog=warehouse).trials == results.trials


def test_the_adapter_the_simulator_and_errors(tmp_path: Path) -> None:
    adapter = trustcbr.Adapter("picking", tmp_path / "picks.db", seed=1, catalog=warehouse)
    behavior = adapter.begin()
    outcome = trustcbr.simulate("picking", behavior, "balanced", seed=2, catalog=warehouse)
    assert adapter.tell_outcome(outcome).kind in {"keep", "switch", "settled"}
    # The plug-in's errors are trustcbr's own exception class.
    with pytest.raises(trustcbr.TrustcbrError, match="unknown scenario `movement`"):
        trustcbr.operators("movement", catalog=warehouse)


def test_the_warehouses_own_arm_serves_and_runs(tmp_path: Path) -> None:
    # The catalog's troubleshooter is an arm like the built-in ones, in the adapter and in
    # a suite.
    assert "troubleshooter" in trustcbr.builtin_arms(catalog=warehouse)
    adapter = trustcbr.Adapter(
        "picking", tmp_path / "picks.db", seed=1, arm="troubleshooter", catalog=warehouse
    )
    adapter.begin({"gripper": "suction", "map": "as-built", "speed": 2.0, "grip_force": 50.0})
    decisions = [
        adapter.tell("interrupted", duration_s=20.0, observed=["safety-stop"]) for _ in range(5)
    ]
    # Five protective stops bring the estimate to -5: the same behavior, only slower.
    switch = decisions[-1]
    assert switch.kind == "switch"
    assert switch.behavior["map"] == "as-built" and switch.behavior["speed"] < 2.0
    # A simulated pick says what the robot perceived, by the names the domain declares.
    pick = {"gripper": "parallel-jaw", "map": "live", "speed": 1.0, "grip_force": 100.0}
    perceived: set[str] = set()
    for seed in range(20):
        outcome = trustcbr.simulate("picking", pick, "balanced", seed, catalog=warehouse)
        perceived |= set(outcome["observed"])
    assert perceived and perceived <= {
        "safety-stop",
        "item-not-found",
        "firm-grip",
        "dropped-item",
        "behind-plan",
    }
    suite = {
        "seed": 3,
        "trials": 4,
        "arms": ["uniform", "troubleshooter", "case-based+troubleshooter"],
        "landscape_runs": 0,
        "limit": {"runs": 0},
        "experiments": [{"scenario": "picking", "operator": "random"}],
    }
    results = trustcbr.run(suite, catalog=warehouse, out=tmp_path / "r")
    assert {t["arm"] for t in results.trials} == set(suite["arms"])


def test_the_gym_environment_over_the_warehouse() -> None:
    pytest.importorskip("gymnasium")
    from trustcbr.gym import TrustEnv

    env = TrustEnv("picking", catalog=warehouse)
    env.reset(seed=0)
    observation, reward, terminated, truncated, info = env.step(env.action_space.sample())
    assert observation[0] >= 1 and reward <= 0
