"""The best arm of each population, picked after the fact: what a benchmark's targets ask.

For docs/search-strategies.md ("What the remaining targets ask"). A benchmark report
compares every arm with each population's known-operator limit. This probe adds the
*hindsight envelope*: on each population, the arm with the lowest mean, chosen after
seeing the trials, and the geometric mean of those minima over the populations. It is not
an arm (no single rule picks a different arm per population before the trials), and the
minimum of many noisy means flatters itself, so a fixed arm whose expected figure equals
the best arm's on every population would still come out above it.

Given several reports of one suite run with different stream sets (the same populations
and arms, the suite's ``seed`` changed), each arm's ratio on a population is first
averaged over them, which takes most of the luck out of the minimum.

For each metric (untrustworthy commands, behaviors evaluated) and each window of trials
(every trial, then 1-50, 51-200 and 201 to the end, the benchmark report's windows):
the envelope's geometric mean over populations, and the named arm's. Then, per arm, the
geometric mean of its untrustworthy commands against the limit and against the population
reference, and on how many populations it needs more than twice that population's best
arm; and the named arm's trials cut off at the suite's command limit, by window:

    python3 docs/probes/hindsight_best.py ARM REPORT [REPORT ...]

Every REPORT is a suite report folder (its ``summary.json`` gives each population's limit
and reference, its ``trials.jsonl`` the trials).
"""

from __future__ import annotations

import json
import math
import sys
from collections import defaultdict
from pathlib import Path
from typing import Any

METRICS = (("untrustworthy", "untrustworthy"), ("behaviors_evaluated", "behaviors"))
"""The trial field and the name printed for each metric."""

WINDOW_STARTS = (1, 51, 201)
"""The first trial (1-based) of each of the benchmark report's windows."""


def geometric_mean(values: list[float]) -> float:
    """The geometric mean of positive values."""
    return math.exp(sum(math.log(v) for v in values) / len(values))


def references(report: Path) -> dict[str, dict[str, float]]:
    """Per population: the limit's behaviors and untrustworthy commands (a random first
    behavior) and the population reference's untrustworthy commands, from
    ``summary.json``."""
    found: dict[str, dict[str, float]] = {}
    for experiment in json.loads((report / "summary.json").read_text())["experiments"]:
        limit = experiment.get("limit")
        if not limit:
            continue
        figures = {
            "behaviors_evaluated": limit["paper_protocol"]["behaviors"],
            "untrustworthy": limit["paper_protocol"]["untrustworthy"],
        }
        reference = limit.get("population_reference")
        if reference:
            figures["reference"] = reference["paper_protocol"]["untrustworthy"]
        found[experiment["name"]] = figures
    return found


def main() -> None:
    arm, *reports = sys.argv[1:]
    # ratio[(population, arm, metric, window)] -> one ratio to the limit per report
    ratio: dict[tuple[str, str, str, int], list[float]] = defaultdict(list)
    to_reference: dict[tuple[str, str], list[float]] = defaultdict(list)
    cut_off: dict[int, int] = defaultdict(int)
    last_trial = 0
    for report in map(Path, reports):
        limits = references(report)
        trials: dict[tuple[str, str], list[dict[str, Any]]] = defaultdict(list)
        with open(report / "trials.jsonl") as lines:
            for line in lines:
                trial = json.loads(line)
                trials[(trial["experiment"], trial["arm"])].append(trial)
                last_trial = max(last_trial, trial["trial"] + 1)
        windows = [(0, last_trial)] + [
            (start - 1, end - 1)
            for start, end in zip(WINDOW_STARTS, WINDOW_STARTS[1:] + (last_trial + 1,))
        ]
        for (population, name), runs in trials.items():
            for field, _ in METRICS:
                for index, (first, end) in enumerate(windows):
                    inside = [t[field] for t in runs if first <= t["trial"] < end]
                    mean = sum(inside) / len(inside)
                    ratio[(population, name, field, index)].append(mean / limits[population][field])
            if "reference" in limits[population]:
                mean = sum(t["untrustworthy"] for t in runs) / len(runs)
                to_reference[(population, name)].append(mean / limits[population]["reference"])
            if name == arm:
                for t in runs:
                    if t["truncated"]:
                        window = max(i for i, s in enumerate(WINDOW_STARTS) if t["trial"] + 1 >= s)
                        cut_off[window] += 1
    populations = sorted({p for p, _, _, _ in ratio}, key=lambda p: (len(p), p))
    arms = sorted({a for _, a, _, _ in ratio})
    averaged = {key: sum(values) / len(values) for key, values in ratio.items()}
    labels = ["every trial"] + [
        f"trials {start}-{end - 1 if end <= last_trial else last_trial}"
        for start, end in zip(WINDOW_STARTS, WINDOW_STARTS[1:] + (last_trial + 1,))
    ]
    print(f"{len(populations)} populations, {len(arms)} arms, {len(reports)} stream set(s)")
    print(f"{'metric':<14} {'window':<16} {'envelope':>9} {arm:>20}")
    for field, shown in METRICS:
        for index, label in enumerate(labels):
            best = [min(averaged[(p, a, field, index)] for a in arms) for p in populations]
            own = [averaged[(p, arm, field, index)] for p in populations]
            print(
                f"{shown:<14} {label:<16} {geometric_mean(best):>9.2f} {geometric_mean(own):>20.2f}"
            )
    best_by_population = {
        p: min(averaged[(p, a, "untrustworthy", 0)] for a in arms) for p in populations
    }
    referenced = [p for p in populations if (p, arm) in to_reference]
    envelope_to_reference = [
        min(sum(to_reference[(p, a)]) / len(to_reference[(p, a)]) for a in arms) for p in referenced
    ]
    print(
        f"untrustworthy x population reference: envelope "
        f"{geometric_mean(envelope_to_reference):.2f}"
    )
    print(f"{'arm':<26} {'x limit':>8} {'x reference':>12} {'> 2x best':>10}")
    for name in arms:
        own = [averaged[(p, name, "untrustworthy", 0)] for p in populations]
        against_reference = [
            sum(to_reference[(p, name)]) / len(to_reference[(p, name)]) for p in referenced
        ]
        above = sum(
            averaged[(p, name, "untrustworthy", 0)] > 2 * best_by_population[p] for p in populations
        )
        print(
            f"{name:<26} {geometric_mean(own):>8.2f} "
            f"{geometric_mean(against_reference):>12.2f} {above:>10}"
        )
    print(
        f"{arm}: trials cut off by window "
        + ", ".join(f"{labels[i + 1]}: {cut_off[i]}" for i in range(len(WINDOW_STARTS)))
    )


if __name__ == "__main__":
    main()
