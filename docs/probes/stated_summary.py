#!/usr/bin/env python3
"""Summarises a run of domains/experiments/stated-SCENARIO.ron (docs/probes/stated_suites.py):
per arm that hears statements and per way of stating (everything rightly, half, 30% wrong),
its behaviors and untrustworthy commands per trial against its twin that ignores them
(`NAME+ignores-statements`) on the same trials, over every instance: the means, the mean
paired difference (hearing minus ignoring) with a 95% confidence interval over the
instances (each instance's mean of its trial-by-trial differences is one observation: the
trials of an arm's chain share what earlier trials learned, so they are not independent,
and one early case can move a whole chain), the instances where hearing is better / worse
by more than its own 95% interval, and the geometric mean over the instances of the
untrustworthy commands as a multiple of the known-operator limit, hearing / ignoring.

usage: docs/probes/stated_summary.py RUN_FOLDER   (prints a markdown table)
"""

import json
import math
import pathlib
import re
import sys

IGNORES = "+ignores-statements"
STATINGS = {"s1": "all, rightly", "s0.5": "half", "s1w0.3": "all, 30% wrong"}


def stating_of(name: str) -> str:
    last = name.rsplit("/", 1)[-1]
    return last if re.fullmatch(r"s[0-9.]+(w[0-9.]+)?", last) else ""


# Student's t at 97.5% for 1 .. 30 degrees of freedom (the normal's 1.96 beyond).
T975 = [
    12.71,
    4.30,
    3.18,
    2.78,
    2.57,
    2.45,
    2.36,
    2.31,
    2.26,
    2.23,
    2.20,
    2.18,
    2.16,
    2.14,
    2.13,
    2.12,
    2.11,
    2.10,
    2.09,
    2.09,
    2.08,
    2.07,
    2.07,
    2.06,
    2.06,
    2.06,
    2.05,
    2.05,
    2.05,
    2.04,
]


def mean_ci(values: list[float]) -> tuple[float, float]:
    n = len(values)
    mean = sum(values) / n
    if n < 2:
        return mean, math.inf
    var = sum((v - mean) ** 2 for v in values) / (n - 1)
    t = T975[n - 2] if n - 1 <= len(T975) else 1.96
    return mean, t * math.sqrt(var / n)


def main() -> None:
    folder = pathlib.Path(sys.argv[1])
    # (experiment, arm, trial) -> (behaviors, untrustworthy)
    trials: dict[tuple[str, str, int], tuple[int, int]] = {}
    for line in (folder / "trials.jsonl").read_text().splitlines():
        t = json.loads(line)
        trials[(t["experiment"], t["arm"], t["trial"])] = (
            t["behaviors_evaluated"],
            t["untrustworthy"],
        )
    summary = json.loads((folder / "summary.json").read_text())
    hearing = [a for a in summary["experiments"][0]["strategies"] if not a.endswith(IGNORES)]
    print(
        "| arm | stated | behaviors, hearing / ignoring | difference "
        "| untrustworthy, hearing / ignoring | difference | instances better / worse "
        "| × limit (geo. mean), hearing / ignoring |"
    )
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for arm in hearing:
        for stating, said in STATINGS.items():
            experiments = [e for e in summary["experiments"] if stating_of(e["name"]) == stating]
            if not experiments:
                continue
            per_instance = [
                [
                    (trials[(e["name"], arm, k)], trials[(e["name"], arm + IGNORES, k)])
                    for k in range(e["trials"])
                ]
                for e in experiments
            ]
            pairs = [p for instance in per_instance for p in instance]
            columns = []
            for at in (0, 1):
                heard = sum(p[0][at] for p in pairs) / len(pairs)
                ignored = sum(p[1][at] for p in pairs) / len(pairs)
                d, ci = mean_ci(
                    [
                        mean_ci([p[0][at] - p[1][at] for p in instance])[0]
                        for instance in per_instance
                    ]
                )
                columns += [f"{heard:.2f} / {ignored:.2f}", f"{d:+.2f} ± {ci:.2f}"]
            # Per instance, on untrustworthy commands: better or worse beyond its interval.
            own = [mean_ci([p[0][1] - p[1][1] for p in instance]) for instance in per_instance]
            better = sum(1 for d, ci in own if d + ci < 0)
            worse = sum(1 for d, ci in own if d - ci > 0)
            columns.append(f"{better} / {worse}")

            def geo(name: str) -> float:
                ratios = [
                    e["strategies"][name]["ratio_to_limit"]["untrustworthy"] for e in experiments
                ]
                return math.exp(sum(math.log(r) for r in ratios) / len(ratios))

            print(
                f"| {arm} | {said} | "
                + " | ".join(columns)
                + f" | {geo(arm):.2f} / {geo(arm + IGNORES):.2f} |"
            )


main()
