#!/usr/bin/env python3
"""Writes domains/experiments/stated-{movement,patrol}.ron: each arm that may hear what an
operator states up front beside its twin that ignores it (`NAME+ignores-statements`, on the
same trials, so the two pair trial by trial), on the evaluation instances eval-0 ..
eval-(COUNT-1) of the benchmark (docs/search-strategies.md, "The benchmark"), each instance
three times: operators who state everything rightly, half of it, and everything with 30% of
it the wrong way round (docs/simulation.md#stated-preferences).

usage: docs/probes/stated_suites.py [COUNT]   (default 20 instances per scenario)
"""

import pathlib
import sys

from benchmark_suites import opening

REPO = pathlib.Path(__file__).resolve().parent.parent.parent
COUNT = int(sys.argv[1]) if len(sys.argv) > 1 else 20
# The built-in arms whose searchers hear statements (the cause-aware search, alone or as a
# fallback), each followed by its twin that ignores them.
HEARING = ["cause-aware", "case-based+cause-aware", "conditioned", "case-based+conditioned"]
ARMS = [name for arm in HEARING for name in (arm, f"{arm}+ignores-statements")]
# What the operators state: (said, wrong).
STATINGS = [(1.0, 0.0), (0.5, 0.0), (1.0, 0.3)]


def suite(scenario: str) -> str:
    file_name = f"stated-{scenario}.ron"
    comment = [
        f'Stated preferences in {scenario} (docs/search-strategies.md, "Stated preferences"):',
        "each arm that hears statements beside its twin that ignores them, on the",
        f"evaluation instances eval-0 .. eval-{COUNT - 1} of the benchmark, each with operators",
        "who state everything rightly, half of it, and everything 30% wrongly; silent",
        "operators otherwise, the paper's adapter. Written by docs/probes/stated_suites.py;",
        f"run it with `trustcbr run domains/experiments/{file_name} --out DIR`.",
    ]
    lines = [*opening(comment, scenario, ARMS), "    experiments: ["]
    for k in range(COUNT):
        folder = REPO / "domains/operators/benchmark" / scenario / f"eval-{k}"
        files = sorted(folder.glob("*.ron"))
        if not files:
            sys.exit(f"{folder}: no members (run docs/probes/benchmark_suites.py's steps first)")
        listed = ", ".join(f'"../operators/benchmark/{scenario}/eval-{k}/{f.name}"' for f in files)
        for said, wrong in STATINGS:
            lines += [
                "        (",
                f'            scenario: "{scenario}",',
                '            operator: "random",',
                f'            population: Some((name: "eval-{k}")),',
                f"            operator_files: [{listed}],",
                f"            stated: Some((said: {said}, wrong: {wrong})),",
                "        ),",
            ]
    lines += ["    ],", ")", ""]
    return "\n".join(lines)


for scenario in ("movement", "patrol"):
    path = REPO / "domains/experiments" / f"stated-{scenario}.ron"
    path.write_text(suite(scenario))
    print(f"wrote {path.relative_to(REPO)}")
