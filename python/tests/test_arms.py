"""Strategies written in Python: arms in the Rust runner, paired with the built-in ones,
reproducible, conformant, and failing loudly."""

from __future__ import annotations

import random
from pathlib import Path
from typing import Any, List, Optional

import pytest

import trustcbr

from conftest import UniformSearcher, small_suite


def run_with_python(**kwargs: Any) -> trustcbr.Results:
    return trustcbr.run(
        small_suite(arms=["random-walk", "py-uniform", "uniform"]),
        python_arms={"py-uniform": UniformSearcher},
        **kwargs,
    )


def test_a_python_arm_runs_paired_with_the_built_in_ones() -> None:
    results = run_with_python()
    arms = results.arms()
    assert list(arms) == ["random-walk", "py-uniform", "uniform"]
    assert arms["py-uniform"]["t_test_p_vs_first"] is not None
    py = [t for t in results.trials if t["arm"] == "py-uniform"]
    builtin = [t for t in results.trials if t["arm"] == "random-walk"]
    assert len(py) == 12
    # Paired: trial k of every arm starts from the same behavior for the same operator.
    assert [t["initial"] for t in py] == [t["initial"] for t in builtin]
    assert all(t["found_trustworthy"] for t in py)
    assert "py-uniform" in results.table or results.summary


def test_a_python_arm_is_reproducible() -> None:
    assert run_with_python().trials == run_with_python().trials


def test_a_case_reusing_python_arm() -> None:
    results = trustcbr.run(
        small_suite(arms=["case-based", "case-based+py"]),
        python_arms={"case-based+py": trustcbr.PythonArm(UniformSearcher, reuses_cases=True)},
    )
    arm = results.arms()["case-based+py"]
    assert arm["reuses_cases"] is True
    assert arm["cases_acquired"] > 0


def test_the_searcher_sees_outcomes_and_episodes() -> None:
    seen: List[UniformSearcher] = []

    class Watching(UniformSearcher):
        learns_across_episodes = True

        def __init__(self, space: trustcbr.Space) -> None:
            super().__init__(space)
            self.episodes = 0
            seen.append(self)

        def end_episode(self, evaluated: Any, settled: Any) -> None:
            self.episodes += 1

    trustcbr.run(small_suite(arms=["random-walk", "watching"]), python_arms={"watching": Watching})
    assert len(seen) == 1
    assert seen[0].episodes == 12
    assert seen[0].observed and {"outcome", "weight", "observed"} <= set(seen[0].observed[0])


def test_the_conformance_kit_passes_a_conformant_searcher() -> None:
    trustcbr.check_searcher(UniformSearcher)


def test_the_conformance_kit_names_the_property_a_searcher_breaks() -> None:
    class Repeating(UniformSearcher):
        def propose(
            self, evaluated: List[trustcbr.Evaluated], rng: random.Random
        ) -> Optional[trustcbr.Behavior]:
            if evaluated:
                return evaluated[0]["behavior"]
            return super().propose(evaluated, rng)

    with pytest.raises(trustcbr.TrustcbrError, match="was already evaluated"):
        trustcbr.check_searcher(Repeating)


def test_a_python_exception_stops_the_run_and_is_raised() -> None:
    class Failing(UniformSearcher):
        def propose(self, evaluated: Any, rng: random.Random) -> Optional[trustcbr.Behavior]:
            raise ValueError("no idea what to try")

    with pytest.raises(ValueError, match="no idea what to try"):
        trustcbr.run(small_suite(arms=["random-walk", "failing"]), python_arms={"failing": Failing})


def test_a_failed_run_writes_no_report(tmp_path: Path) -> None:
    class Failing(UniformSearcher):
        def propose(self, evaluated: Any, rng: random.Random) -> Optional[trustcbr.Behavior]:
            raise RuntimeError("broken")

    out = tmp_path / "report"
    with pytest.raises(RuntimeError, match="broken"):
        trustcbr.run(
            small_suite(arms=["random-walk", "failing"]),
            python_arms={"failing": Failing},
            out=out,
            save_cases=tmp_path / "cases",
        )
    assert not (out / "trials.jsonl").exists()
    assert not any((tmp_path / "cases").iterdir())


def test_a_proposal_outside_the_space_is_refused() -> None:
    class Wild(UniformSearcher):
        def propose(self, evaluated: Any, rng: random.Random) -> Optional[trustcbr.Behavior]:
            return {"speed": 1000.0, "padding": 0.2}

    with pytest.raises(trustcbr.TrustcbrError, match="propose returned"):
        trustcbr.run(small_suite(arms=["random-walk", "wild"]), python_arms={"wild": Wild})


def test_a_rationale_that_expects_reaches_the_explanations(tmp_path: Path) -> None:
    class Expecting(UniformSearcher):
        def rationale(self, proposed: trustcbr.Behavior) -> Any:
            return {"expects": "fewer surprises", "confidence": 0.8}

    out = tmp_path / "report"
    trustcbr.run(
        small_suite(arms=["random-walk", "expecting"]),
        python_arms={"expecting": Expecting},
        out=out,
    )
    page = (out / "report.html").read_text(encoding="utf-8")
    assert "expecting search, expecting fewer surprises (confidence 80%)" in page


def test_a_rationale_of_another_type_is_refused() -> None:
    class Vague(UniformSearcher):
        def rationale(self, proposed: trustcbr.Behavior) -> Any:
            return {"hopes": "something"}

    with pytest.raises(TypeError, match="must return a str"):
        trustcbr.run(small_suite(arms=["random-walk", "vague"]), python_arms={"vague": Vague})
