"""The ask/tell adapter: episodes, decisions with explanations, case bases, errors."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

import trustcbr


def test_an_episode_switches_with_an_explanation_and_settles_retaining_a_case(
    tmp_path: Path,
) -> None:
    adapter = trustcbr.Adapter("movement", tmp_path / "cases.db", seed=3)
    start = adapter.begin({"speed": 9.5, "padding": 0.2})
    assert start == {"speed": 9.5, "padding": 0.2}
    decisions = [
        adapter.tell("interrupted", duration_s=10.0, observed=["collision"]) for _ in range(5)
    ]
    assert [d.kind for d in decisions[:4]] == ["keep"] * 4
    switch = decisions[4]
    assert switch.kind == "switch"
    assert switch.behavior != start
    assert switch.explanation is not None
    assert "collision" in (switch.sentence or "")
    decision = switch
    for _ in range(5):
        decision = adapter.tell("completed", duration_s=10.0)
    assert decision.kind == "settled"
    assert decision.reply["trustworthy"] is True
    assert decision.reply["retained"] == 1
    assert decision.behavior == switch.behavior
    assert len(adapter.cases()) == 1
    # A second adapter on the same base sees the case.
    other = trustcbr.Adapter("movement", tmp_path / "cases.db")
    assert other.state()["cases"] == 1


def test_refused_requests_raise_the_servers_messages_and_change_nothing(tmp_path: Path) -> None:
    adapter = trustcbr.Adapter("patrol", tmp_path / "cases.db")
    with pytest.raises(trustcbr.TrustcbrError, match="no episode is under way"):
        adapter.tell("completed")
    adapter.begin()
    before = adapter.state()
    with pytest.raises(trustcbr.TrustcbrError, match="unknown variant `exploded`"):
        adapter.tell("exploded")
    with pytest.raises(
        trustcbr.TrustcbrError, match="field `observed`: observation `smoke` is not declared"
    ):
        adapter.tell("failed", observed=["smoke"])
    with pytest.raises(trustcbr.TrustcbrError, match="field `stated`"):
        adapter.tell("failed", stated="boredom")
    with pytest.raises(trustcbr.TrustcbrError, match="field `weight`"):
        adapter.tell("failed", weight=float("nan"))
    with pytest.raises(trustcbr.TrustcbrError, match="an episode is already under way"):
        adapter.begin()
    assert adapter.state() == before
    with pytest.raises(trustcbr.TrustcbrError, match="field `behavior`"):
        trustcbr.Adapter("movement", tmp_path / "other.db").begin({"speed": 99.0, "padding": 0.2})


def test_unknown_domains_and_arms_are_refused_naming_the_known_ones(tmp_path: Path) -> None:
    with pytest.raises(
        trustcbr.TrustcbrError, match=r"neither a built-in domain \(movement, patrol\)"
    ):
        trustcbr.Adapter("warehouse", tmp_path / "c.db")
    # In the words of the call (arm=), not the command line's (--arm).
    with pytest.raises(trustcbr.TrustcbrError, match=r"^arm: unknown arm `annealing` \(known: "):
        trustcbr.Adapter("movement", tmp_path / "c.db", arm="annealing")
    assert not (tmp_path / "c.db").exists()
    with pytest.raises(trustcbr.TrustcbrError, match=r"^competence: .* is 2; it must be a chance"):
        trustcbr.Adapter("movement", tmp_path / "c.db", mission=True, competence=2.0)


def test_a_domain_file_and_an_arm_are_served(tmp_path: Path) -> None:
    domain = Path(__file__).resolve().parents[2] / "examples" / "domain.ron"
    adapter = trustcbr.Adapter(str(domain), tmp_path / "w.db", arm="case-based+cause-aware")
    config = adapter.config()
    assert config["strategy"]
    assert adapter.writable
    adapter.begin()
    assert adapter.abandon()["ok"] == "abandoned"


def test_the_recommended_arm_is_served_unless_another_or_the_domain_s_own_is_named(
    tmp_path: Path,
) -> None:
    assert trustcbr.RECOMMENDED_ARM == "case-based+nested"
    assert trustcbr.RECOMMENDED_ARM in trustcbr.builtin_arms()
    served = trustcbr.Adapter("movement", tmp_path / "a.db").config()
    assert served["strategy"] == "nested"
    assert served["adapter"]["reuse_cases"] is True
    # The paper's arms by name, and the domain's own config (the paper's case-based
    # strategy for a built-in scenario) with "domain".
    paper = trustcbr.Adapter("movement", tmp_path / "b.db", arm="case-based").config()
    assert paper["strategy"] == "random-walk"
    own = trustcbr.Adapter("movement", tmp_path / "c.db", arm="domain").config()
    assert own["strategy"] == "random-walk"
    assert own["adapter"]["search"] == "random_walk"


def test_the_same_seed_gives_the_same_episode(tmp_path: Path) -> None:
    def episode(path: Path) -> list[str]:
        adapter = trustcbr.Adapter("movement", path, seed=11)
        adapter.begin()
        seen = []
        for _ in range(15):
            decision = adapter.tell("interrupted", duration_s=3.0)
            seen.append(repr(decision))
        return seen

    assert episode(tmp_path / "a.db") == episode(tmp_path / "b.db")


def test_simulated_outcomes_can_be_told_to_the_adapter(tmp_path: Path) -> None:
    adapter = trustcbr.Adapter("movement", tmp_path / "cases.db", seed=1)
    behavior = adapter.begin()
    for seed in range(200):
        outcome = trustcbr.simulate("movement", behavior, "balanced", seed=seed)
        decision = adapter.tell_outcome(outcome)
        behavior = decision.behavior
        if decision.kind == "settled":
            break
    assert decision.kind == "settled"


def test_a_change_detector_gives_a_long_trusted_behavior_up_sooner(tmp_path: Path) -> None:
    def fourth_interruption(path: Path, detect_changes: bool) -> str:
        adapter = trustcbr.Adapter(
            "movement", path, seed=3, mission=True, detect_changes=detect_changes
        )
        adapter.begin({"speed": 3.5, "padding": 0.4})
        # Settled after five completions, then trusted for a hundred more: the detector
        # bounds the behavior's rate of untrustworthy commands at 0.028, and four
        # interruptions in a row pass its threshold; the paper's watch needs ten.
        for _ in range(105):
            adapter.tell("completed", duration_s=2.0)
        kinds = [adapter.tell("interrupted", duration_s=2.0).kind for _ in range(4)]
        assert kinds[:3] == ["keep"] * 3
        return kinds[3]

    assert fourth_interruption(tmp_path / "a.db", True) == "switch"
    assert fourth_interruption(tmp_path / "b.db", False) == "keep"
    with pytest.raises(trustcbr.TrustcbrError, match="^detect_changes: .* pass mission=True$"):
        trustcbr.Adapter("movement", tmp_path / "c.db", detect_changes=True)
    assert not (tmp_path / "c.db").exists()


def test_a_mission_keeps_listening_after_settling_and_alerts(tmp_path: Path) -> None:
    adapter = trustcbr.Adapter("movement", tmp_path / "cases.db", seed=3, mission=True)
    assert adapter.config()["adapter"]["mode"] == "mission"
    start = adapter.begin({"speed": 3.5, "padding": 0.4})
    # While deciding, the operator interrupts three bumps the robot felt, then lets eight
    # commands complete: -3 + 8 = +5, settled.
    for _ in range(3):
        adapter.tell("interrupted", duration_s=2.0, observed=["collision"])
    decisions = [adapter.tell("completed", duration_s=2.0) for _ in range(8)]
    assert decisions[-1].kind == "settled"

    # After settling, outcomes are answered for the watched behavior, its trust capped;
    # the robot now feels bumps the operator lets pass (and is sure of its commands).
    def bump() -> trustcbr.Decision:
        return adapter.tell("completed", duration_s=2.0, observed=["collision"], confidence=0.95)

    kept = bump()
    assert (kept.kind, kept.behavior, kept.reply["trust"]) == ("keep", start, 5.0)
    assert adapter.state()["watching"]["behavior"] == start
    # Each bump let pass adds ln 6.625 to the robot's evidence that the operator has
    # stopped watching (docs/protocol.md, "Mission mode"): the third passes ln 100 and the
    # robot asks for supervision.
    bumps = [bump() for _ in range(2)]
    assert [d.kind for d in bumps] == ["keep", "alert"]
    alert = bumps[-1]
    assert alert.behavior == start
    assert alert.reply["trust"] == 5.0
    assert alert.reply["own_record"] >= math.log(100)
    assert (alert.sentence or "").startswith("Please supervise speed=3.5 m/s, padding=0.4 m")
    # Ten interruptions give the watched behavior up: a new episode starts with a switch.
    falls = [adapter.tell("interrupted", duration_s=2.0) for _ in range(10)]
    assert [d.kind for d in falls] == ["keep"] * 9 + ["switch"]
    assert falls[-1].explanation is not None
    assert falls[-1].explanation["given_up"]["behavior"] == start
    assert adapter.state()["watching"] is None
    with pytest.raises(
        trustcbr.TrustcbrError, match=r"confidence must be a number in \[0, 1\], got 1.5"
    ):
        adapter.tell("completed", confidence=1.5)


def test_a_robot_judging_its_competence_asks_to_choose_once(tmp_path: Path) -> None:
    adapter = trustcbr.Adapter(
        "movement", tmp_path / "cases.db", seed=3, mission=True, competence=0.1
    )
    start = adapter.begin({"speed": 3.5, "padding": 0.4})
    # Every command completes and bumps something: settled after five, and on the first
    # watched command the robot's own record (6 bumps in 6) is surely above 1 in 10.
    decisions = [
        adapter.tell("completed", duration_s=2.0, observed=["collision"]) for _ in range(8)
    ]
    assert [d.kind for d in decisions] == ["keep"] * 4 + ["settled", "overtrust", "keep", "keep"]
    overtrust = decisions[5]
    assert (overtrust.behavior, overtrust.trust, overtrust.short) == (start, 5.0, ["collision"])
    assert overtrust.reply["competence"]["commands"] == 6
    assert (overtrust.sentence or "").startswith("Please choose: the operator trusts speed=3.5")
    # No operator trusted anything before: nothing to offer, and nothing to take.
    assert overtrust.offer is None
    with pytest.raises(trustcbr.TrustcbrError, match="no offer to accept"):
        adapter.accept_offer()
    with pytest.raises(trustcbr.TrustcbrError, match="pass mission=True"):
        trustcbr.Adapter("movement", tmp_path / "other.db", competence=0.1)
    with pytest.raises(trustcbr.TrustcbrError, match="must be a chance in"):
        trustcbr.Adapter("movement", tmp_path / "other.db", mission=True, competence=2.0)
    assert not (tmp_path / "other.db").exists()


def test_an_overtrust_alert_offers_a_safer_behavior_to_take(tmp_path: Path) -> None:
    adapter = trustcbr.Adapter(
        "movement", tmp_path / "cases.db", seed=3, mission=True, competence=0.1
    )
    # A first operator gives up its first behavior and trusts the one the search finds
    # (retained as a case), which then runs 40 more commands without a bump.
    adapter.begin({"speed": 3.5, "padding": 0.4})
    switch = [adapter.tell("interrupted", duration_s=2.0) for _ in range(5)][-1]
    assert switch.kind == "switch"
    for _ in range(45):
        adapter.tell("completed", duration_s=2.0)
    adapter.abandon()
    # The next operator trusts a behavior that bumps every time.
    adapter.begin({"speed": 3.5, "padding": 0.4})
    decisions = [
        adapter.tell("completed", duration_s=2.0, observed=["collision"]) for _ in range(6)
    ]
    overtrust = decisions[-1]
    assert overtrust.kind == "overtrust"
    assert overtrust.offer == switch.behavior
    assert adapter.accept_offer() == switch.behavior
    assert adapter.state()["watching"]["behavior"] == switch.behavior


def test_an_arm_preferring_competent_behaviors_passes_over_one(tmp_path: Path) -> None:
    adapter = trustcbr.Adapter(
        "movement",
        tmp_path / "cases.db",
        arm="uniform+competent",
        mission=True,
        competence=0.1,
    )
    start = adapter.begin({"speed": 3.5, "padding": 0.4})
    decisions = [
        adapter.tell("completed", duration_s=2.0, observed=["collision"]) for _ in range(5)
    ]
    # Trusted on the fifth, but surely not competent: given up, and the search goes on.
    assert [d.kind for d in decisions] == ["keep"] * 4 + ["switch"]
    assert decisions[-1].behavior != start
    with pytest.raises(
        trustcbr.TrustcbrError, match="^arm: .* pass mission=True, competence=AT_MOST$"
    ):
        trustcbr.Adapter("movement", tmp_path / "other.db", arm="uniform+competent", mission=True)
    assert not (tmp_path / "other.db").exists()


def test_without_mission_outcomes_after_settling_are_refused(tmp_path: Path) -> None:
    adapter = trustcbr.Adapter("movement", tmp_path / "cases.db")
    adapter.begin({"speed": 3.5, "padding": 0.4})
    assert [adapter.tell("completed").kind for _ in range(5)][-1] == "settled"
    assert "watching" not in adapter.state()
    with pytest.raises(trustcbr.TrustcbrError, match="no episode is under way"):
        adapter.tell("completed")


def test_a_said_goal_change_counts_against_nothing(tmp_path: Path) -> None:
    adapter = trustcbr.Adapter("movement", tmp_path / "cases.db", seed=3)
    start = adapter.begin({"speed": 9.5, "padding": 0.2})
    first = adapter.tell("interrupted", duration_s=10.0, observed=["collision"])
    assert first.kind == "keep"
    # Any number of said goal changes: the behavior is kept and its trust unchanged.
    for _ in range(10):
        decision = adapter.tell("interrupted", duration_s=4.0, goal_change=True)
        assert decision.kind == "keep"
        assert decision.behavior == start
        assert decision.trust == first.trust == -1.0
    episode = adapter.state()["episode"]
    assert (episode["commands"], episode["behavior_commands"]) == (11, 1)
    # Said only of an interruption, and never beside a reason.
    with pytest.raises(trustcbr.TrustcbrError, match="goal_change is said only of an interruption"):
        adapter.tell("completed", goal_change=True)
    with pytest.raises(trustcbr.TrustcbrError, match="with a stated reason"):
        adapter.tell("interrupted", stated="collision", goal_change=True)
    # Unsaid, a goal change is an interruption like any other: four more give it up.
    decisions = [adapter.tell("interrupted", duration_s=4.0) for _ in range(4)]
    assert decisions[-1].kind == "switch"


def test_a_case_is_learned_and_reused_in_its_context(tmp_path: Path) -> None:
    adapter = trustcbr.Adapter("movement", tmp_path / "cases.db", seed=3)
    assert adapter.context == {}
    first = {"speed": 9.5, "padding": 0.2}

    def give_up_first() -> trustcbr.Decision:
        decision = adapter.tell("interrupted", duration_s=10.0)
        while decision.kind == "keep":
            decision = adapter.tell("interrupted", duration_s=10.0)
        return decision

    adapter.begin(first, context={"cargo": "hazardous"})
    assert adapter.context == {"cargo": "hazardous"}
    assert give_up_first().reply["source"] == "search"
    decision = adapter.tell("completed", duration_s=10.0)
    while decision.kind != "settled":
        decision = adapter.tell("completed", duration_s=10.0)
    [case] = adapter.cases()
    assert case["context"] == {"cargo": "hazardous"}
    # In another context the same start finds no case; in the same one it reuses it.
    assert adapter.set_context({"situation": "emergency"}) == {"situation": "emergency"}
    adapter.begin(first)
    assert give_up_first().reply["source"] == "search"
    adapter.abandon()
    adapter.begin(first, context={"cargo": "hazardous"})
    reused = give_up_first()
    assert reused.reply["source"] == "case"
    assert reused.behavior == case["solution"]
    with pytest.raises(trustcbr.TrustcbrError, match="an episode is under way"):
        adapter.set_context({})
    adapter.abandon()
    with pytest.raises(trustcbr.TrustcbrError, match="may be normal, hazardous, not `toxic`"):
        adapter.set_context({"cargo": "toxic"})
    assert adapter.context == {"cargo": "hazardous"}
    assert adapter.set_context({}) == {}
    assert adapter.context == {}


def test_an_operator_states_its_preferences_as_an_episode_begins(tmp_path: Path) -> None:
    adapter = trustcbr.Adapter("movement", tmp_path / "cases.db", arm="cause-aware", seed=3)
    assert adapter.config()["statements"] == [
        "hurry",
        "avoid-bumps",
        "keep-away-from-people",
        "keep-clear",
    ]
    with pytest.raises(trustcbr.TrustcbrError, match="`fly` is not a statement of this domain"):
        adapter.begin(preferences={"fly": True})
    assert adapter.state()["episode"] is None
    begun = adapter.begin({"speed": 9.5, "padding": 0.2}, preferences={"avoid-bumps": True})
    assert begun == {"speed": 9.5, "padding": 0.2}


def test_a_robot_on_a_mission_goes_back_to_what_it_settled_on_in_a_context(tmp_path: Path) -> None:
    adapter = trustcbr.Adapter("movement", tmp_path / "cases.db", seed=1, mission=True)
    with pytest.raises(trustcbr.TrustcbrError, match="once a behavior is in use"):
        adapter.switch_context({"cargo": "hazardous"})
    start = adapter.begin({"speed": 3.5, "padding": 0.4})
    decisions = [adapter.tell("completed", duration_s=8.5) for _ in range(5)]
    assert decisions[-1].kind == "settled"
    kept = adapter.switch_context({"cargo": "hazardous"})
    assert kept == trustcbr.ContextSwitch(start, "kept", False, {"cargo": "hazardous"})
    # The operator minds it with hazardous cargo: ten interruptions give it up, and five
    # completions settle the next.
    falls = [adapter.tell("interrupted", duration_s=10.0) for _ in range(10)]
    assert falls[-1].kind == "switch"
    settled = [adapter.tell("completed", duration_s=8.5) for _ in range(5)][-1]
    assert settled.kind == "settled" and settled.behavior != start
    back = adapter.switch_context({})
    assert (back.behavior, back.origin, back.gave_up_watch) == (start, "resumed", True)
    assert adapter.state()["episode"]["behavior"] == start
    # Outside mission mode there is no switch to tell of.
    episodes = trustcbr.Adapter("movement", tmp_path / "other.db", seed=1)
    episodes.begin()
    with pytest.raises(trustcbr.TrustcbrError, match="mission=True"):
        episodes.switch_context({"cargo": "hazardous"})
