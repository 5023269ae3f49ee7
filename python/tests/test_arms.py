"""Strategies written in Python: arms in the Rust runner, paired with the built-in ones,
reproducible, conformant, and failing loudly."""

from __future__ import annotations

import os
import random
import re
import shutil
import subprocess
import sys
from pathlib import Path
from typing import Any, List, Optional

import pytest

import trustcbr

from conftest import UniformSearcher, small_suite

BIN = os.environ.get("TRUSTCBR_BIN") or shutil.which("trustcbr")


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


def test_case_reuse_passes_over_what_a_python_searcher_doubts() -> None:
    asked: List[Any] = []

    class Doubting(UniformSearcher):
        def doubts(self, evaluated: List[Any], behavior: Any) -> bool:
            asked.append((len(evaluated), behavior))
            return True

    results = trustcbr.run(
        small_suite(arms=["case-based+py", "case-based+doubting"], trials=40),
        python_arms={
            "case-based+py": trustcbr.PythonArm(UniformSearcher, reuses_cases=True),
            "case-based+doubting": trustcbr.PythonArm(Doubting, reuses_cases=True),
        },
    )
    reused = {
        arm: sum(t["reused"] for t in results.trials if t["arm"] == arm)
        for arm in ("case-based+py", "case-based+doubting")
    }
    assert reused["case-based+py"] > 0
    # Every case was doubted: none reused, and the searcher was asked about each solution
    # after at least one rejection, as a behavior of the space.
    assert reused["case-based+doubting"] == 0
    assert asked and all(n >= 1 and set(b) == {"speed", "padding"} for n, b in asked)


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


def test_the_searcher_is_told_the_robots_context_and_a_blind_twin_is_not() -> None:
    told: List[List[Any]] = []

    class Contextual(UniformSearcher):
        learns_across_episodes = True

        def __init__(self, space: trustcbr.Space) -> None:
            super().__init__(space)
            self.contexts: List[Any] = []
            told.append(self.contexts)

        def enter_context(self, context: Any) -> None:
            self.contexts.append(context)

    cycle = [{}, {"cargo": "hazardous"}]
    experiment = {"scenario": "movement", "operator": "balanced", "contexts": {"cycle": cycle}}
    trustcbr.run(
        small_suite(arms=["contextual", "contextual+context-blind"], experiments=[experiment]),
        python_arms={"contextual": Contextual},
    )
    # One searcher for each arm's chain of trials: told the trial's context, or none.
    assert len(told) == 2 and cycle * 6 in told and [{}] * 12 in told


def test_the_searcher_hears_what_operators_state_and_a_deaf_twin_does_not() -> None:
    heard: List[List[Any]] = []

    class Listening(UniformSearcher):
        learns_across_episodes = True

        def __init__(self, space: trustcbr.Space) -> None:
            super().__init__(space)
            self.stated: List[Any] = []
            heard.append(self.stated)

        def hear(self, stated: Any) -> None:
            self.stated.append(stated)

    experiment = {"scenario": "movement", "operator": "balanced", "stated": {"said": 1.0}}
    trustcbr.run(
        small_suite(arms=["listening", "listening+ignores-statements"], experiments=[experiment]),
        python_arms={"listening": Listening},
    )
    # The balanced operator minds lateness and bumps, and has neither of the other two
    # preferences (domains/operators/movement/balanced.ron).
    truth = [
        {"name": "hurry", "minds": True},
        {"name": "avoid-bumps", "minds": True},
        {"name": "keep-away-from-people", "minds": False},
        {"name": "keep-clear", "minds": False},
    ]
    assert len(heard) == 2 and [truth] * 12 in heard and [[]] * 12 in heard


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

    with pytest.raises(trustcbr.SearcherCheckError, match="already evaluated"):
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
    # Nothing written, not even the folders the run would have written into.
    assert not out.exists()
    assert not (tmp_path / "cases").exists()


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


def test_a_python_arm_named_like_a_built_in_one_is_refused() -> None:
    with pytest.raises(
        trustcbr.TrustcbrError, match="python_arms: `uniform` is the name of a built-in arm"
    ):
        trustcbr.run(
            small_suite(arms=["random-walk", "uniform"]), python_arms={"uniform": UniformSearcher}
        )


def test_a_python_arm_not_run_is_refused() -> None:
    with pytest.raises(
        trustcbr.TrustcbrError,
        match=r"python_arms: `mine` is not among the arms run \(random-walk, case-based\)",
    ):
        trustcbr.run(small_suite(), python_arms={"mine": UniformSearcher})


class GlobalRandom(UniformSearcher):
    """Draws from the module `random`, not from the generator it is given."""

    def propose(
        self, evaluated: List[trustcbr.Evaluated], rng: random.Random
    ) -> Optional[trustcbr.Behavior]:
        return super().propose(evaluated, random.Random(random.getrandbits(64)))


class Remembering(UniformSearcher):
    """Carries what it saw from one episode to the next without saying so."""

    def __init__(self, space: trustcbr.Space) -> None:
        super().__init__(space)
        self.episodes = 0

    def propose(
        self, evaluated: List[trustcbr.Evaluated], rng: random.Random
    ) -> Optional[trustcbr.Behavior]:
        for _ in range(self.episodes):
            rng.random()
        return super().propose(evaluated, rng)

    def end_episode(self, evaluated: Any, settled: Any) -> None:
        self.episodes += 1


@pytest.mark.parametrize(
    "searcher, rule, advice",
    [
        (GlobalRandom, "deterministic", "draw every random number from the `rng`"),
        (Remembering, "forgets-unless-it-learns", "set `learns_across_episodes = True`"),
    ],
)
def test_the_kit_raises_one_exception_with_the_rule_the_case_and_the_right_advice(
    searcher: Any, rule: str, advice: str
) -> None:
    with pytest.raises(trustcbr.SearcherCheckError) as raised:
        trustcbr.check_searcher(searcher)
    error = raised.value
    assert isinstance(error, trustcbr.TrustcbrError)
    assert error.rule == rule
    message = str(error)
    assert message.startswith(f"the searcher breaks the rule `{rule}`")
    assert advice in message
    # In Python terms: the space's components by name, no Rust in sight.
    assert "on a space of" in message and "Behavior(" not in message and "Proposal" not in message


def test_the_kit_names_the_repeated_behavior_as_a_dict() -> None:
    class Repeating(UniformSearcher):
        """Repeats the first behavior while others are untried."""

        def propose(
            self, evaluated: List[trustcbr.Evaluated], rng: random.Random
        ) -> Optional[trustcbr.Behavior]:
            if len(evaluated) == 1 and self.size > 1:
                return evaluated[0]["behavior"]
            return super().propose(evaluated, rng)

    with pytest.raises(trustcbr.SearcherCheckError) as raised:
        trustcbr.check_searcher(Repeating)
    assert raised.value.rule == "untried"
    assert raised.value.proposal is not None
    assert raised.value.proposal["returned"] == raised.value.evaluated[0]["behavior"]
    message = str(raised.value)
    assert re.search(
        r"which was already evaluated, while \d+ of \d+ behaviors were untried", message
    )
    assert "To fix it: return a behavior not in `evaluated` while any is untried" in message


def test_a_strategy_for_a_named_domain_is_checked_on_its_space() -> None:
    class SlowFirst(UniformSearcher):
        """Reads the patrol space's own components by name."""

        def propose(
            self, evaluated: List[trustcbr.Evaluated], rng: random.Random
        ) -> Optional[trustcbr.Behavior]:
            speeds = [c for c in self.components if c[0] == "speed"][0][1]
            assert speeds
            return super().propose(evaluated, rng)

    with pytest.raises(IndexError):
        trustcbr.check_searcher(SlowFirst)  # random spaces have components c0, c1, ...
    trustcbr.check_searcher(SlowFirst, scenario="movement")


def test_explain_replays_a_reports_built_in_arms_and_names_the_python_ones(tmp_path: Path) -> None:
    out = tmp_path / "report"
    results = trustcbr.run(
        small_suite(arms=["random-walk", "py-uniform"]),
        python_arms={"py-uniform": UniformSearcher},
        out=out,
    )
    told = trustcbr.explain(out, experiment="movement/balanced", arm="random-walk", trial=3)
    assert told.story.startswith("movement/balanced, arm random-walk, trial 3")
    ran = [t for t in results.trials if t["arm"] == "random-walk" and t["trial"] == 3][0]
    assert told.record["report"]["behaviors_evaluated"] == ran["behaviors_evaluated"]
    with pytest.raises(
        trustcbr.TrustcbrError,
        match=r"arm `py-uniform` cannot be replayed.*the report's replayable arms: random-walk",
    ):
        trustcbr.explain(out, experiment="movement/balanced", arm="py-uniform", trial=3)
    # Given its factory, the Python arm is replayed too.
    again = trustcbr.explain(
        out,
        experiment="movement/balanced",
        arm="py-uniform",
        trial=3,
        python_arms={"py-uniform": UniformSearcher},
    )
    py = [t for t in results.trials if t["arm"] == "py-uniform" and t["trial"] == 3][0]
    assert again.record["report"]["behaviors_evaluated"] == py["behaviors_evaluated"]


@pytest.mark.skipif(BIN is None, reason="set TRUSTCBR_BIN to the trustcbr binary")
def test_the_command_lines_explain_reads_a_report_with_python_arms(tmp_path: Path) -> None:
    assert BIN is not None
    out = tmp_path / "report"
    trustcbr.run(
        small_suite(arms=["random-walk", "py-uniform"]),
        python_arms={"py-uniform": UniformSearcher},
        out=out,
    )
    args = [BIN, "explain", str(out), "--experiment", "movement/balanced", "--trial", "2"]
    told = subprocess.run([*args, "--arm", "random-walk"], capture_output=True, text=True)
    assert told.returncode == 0, told.stderr
    assert told.stdout == str(
        trustcbr.explain(out, experiment="movement/balanced", arm="random-walk", trial=2)
    )
    refused = subprocess.run([*args, "--arm", "py-uniform"], capture_output=True, text=True)
    assert refused.returncode != 0
    assert "arm `py-uniform` cannot be replayed" in refused.stderr
    assert "replayable arms: random-walk" in refused.stderr


def test_the_built_in_arms_are_the_registry_s_strategies_alone_then_after_case_reuse() -> None:
    strategies = trustcbr.strategies()
    assert strategies[0]["name"] == "random-walk"
    assert strategies[0]["case_based"] == "case-based"
    expected = []
    for strategy in strategies:
        assert strategy["description"]
        expected.append(strategy["name"])
        if strategy["case_based"] is not None:
            expected.append(strategy["case_based"])
    assert trustcbr.builtin_arms()[: len(expected)] == expected
    learning = {s["name"] for s in strategies if s["learns_across_episodes"]}
    assert "conditioned" in learning and "random-walk" not in learning


def test_the_kit_tells_a_searcher_that_repeats_once_all_were_tried_to_return_none() -> None:
    class NeverDone(UniformSearcher):
        """Repeats the first behavior once every behavior was tried, instead of None."""

        def propose(
            self, evaluated: List[trustcbr.Evaluated], rng: random.Random
        ) -> Optional[trustcbr.Behavior]:
            chosen = super().propose(evaluated, rng)
            return chosen if chosen is not None else evaluated[0]["behavior"]

    with pytest.raises(trustcbr.SearcherCheckError) as raised:
        trustcbr.check_searcher(NeverDone)
    message = str(raised.value)
    assert raised.value.rule == "untried"
    assert "when every behavior of the space was evaluated" in message
    assert "To fix it: return None once every behavior of the space is in `evaluated`" in message
    assert "while any is untried" not in message


def test_the_kit_tells_a_searcher_that_stops_early_to_return_an_untried_one() -> None:
    class Quitter(UniformSearcher):
        def propose(
            self, evaluated: List[trustcbr.Evaluated], rng: random.Random
        ) -> Optional[trustcbr.Behavior]:
            return None if evaluated else super().propose(evaluated, rng)

    with pytest.raises(trustcbr.SearcherCheckError) as raised:
        trustcbr.check_searcher(Quitter)
    message = str(raised.value)
    assert raised.value.rule == "exhausted-only-when-all-tried"
    assert re.search(r"propose\(\) returned None while \d+ of \d+ behaviors were untried", message)
    assert "To fix it: return one of the untried behaviors" in message


class NoSpace:
    """A factory that forgot the space: ``NoSpace(space)`` raises TypeError."""

    def __init__(self) -> None:
        pass

    def propose(self, evaluated: Any, rng: random.Random) -> None:
        return None


def test_a_bad_factory_is_named_by_its_arm(tmp_path: Path) -> None:
    suite = small_suite(arms=["random-walk", "mine"])
    with pytest.raises(trustcbr.TrustcbrError) as raised:
        trustcbr.run(suite, python_arms={"mine": NoSpace})
    message = str(raised.value)
    assert message.startswith("python_arms['mine']: the factory raised TypeError(")
    assert "when called with the space (speed, padding)" in message
    assert isinstance(raised.value.__cause__, TypeError)
    with pytest.raises(trustcbr.TrustcbrError, match=r"^python_arms\['mine'\]: a factory .*int 42"):
        trustcbr.run(suite, python_arms={"mine": 42})  # type: ignore[dict-item]
    with pytest.raises(
        trustcbr.TrustcbrError,
        match=r"^python_arms\['mine'\]: the factory returned 'a str'.*propose",
    ):
        trustcbr.run(suite, python_arms={"mine": lambda space: "a str"})  # type: ignore[dict-item]
    with pytest.raises(trustcbr.TrustcbrError, match=r"^strategy: the factory raised TypeError"):
        trustcbr.Adapter("movement", tmp_path / "c.db", strategy=NoSpace)  # type: ignore[arg-type]
    with pytest.raises(trustcbr.TrustcbrError, match=r"^factory: a factory"):
        trustcbr.check_searcher("UniformSearcher")  # type: ignore[arg-type]


@pytest.mark.skipif(sys.version_info < (3, 11), reason="exception notes are Python 3.11's")
def test_a_searchers_exception_says_which_arm_raised_it() -> None:
    class Failing(UniformSearcher):
        def propose(self, evaluated: Any, rng: random.Random) -> Optional[trustcbr.Behavior]:
            raise ValueError("no idea what to try")

    with pytest.raises(ValueError) as raised:
        trustcbr.run(small_suite(arms=["random-walk", "failing"]), python_arms={"failing": Failing})
    assert getattr(raised.value, "__notes__", []) == [
        "raised by propose() of python_arms['failing']"
    ]
