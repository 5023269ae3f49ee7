#!/usr/bin/env python3
"""Writes domains/experiments/benchmark-{movement,patrol}.ron: every arm on the evaluation
instances eval-0 .. eval-(COUNT-1) of the prior (docs/simulation.md, "Operators no one
designed"), whose members `trustcbr population` wrote to
domains/operators/benchmark/SCENARIO/eval-K/ (run it first; docs/search-strategies.md,
"The benchmark").

usage: docs/probes/benchmark_suites.py [COUNT]   (default 20 instances; trials per scenario:
TRIALS, chosen so that a suite runs within 10 minutes on the project's 2-core machine)
"""
import pathlib
import sys

REPO = pathlib.Path(__file__).resolve().parent.parent.parent
COUNT = int(sys.argv[1]) if len(sys.argv) > 1 else 20
TRIALS = {"movement": 500, "patrol": 300}
# A trial's commands are capped (the trial is then truncated, counted as not settled): the
# paper's random walk needs thousands of commands a trial on a population with a small
# trustworthy region, and would alone exceed the suite's 10 minutes.
MAX_COMMANDS = 2000
ARMS = [
    "random-walk", "case-based", "uniform", "cause-aware", "model-based", "conditioned",
    "case-based+cause-aware", "case-based+model-based", "case-based+conditioned",
]


def suite(scenario: str) -> str:
    lines = [
        f"// The benchmark for {scenario} (docs/search-strategies.md, \"The benchmark\"): every arm",
        f"// on the evaluation instances eval-0 .. eval-{COUNT - 1} of the prior ugv-1, silent operators,",
        "// the paper's adapter. Nothing in any strategy was chosen on these instances. Written by",
        "// docs/probes/benchmark_suites.py; run it with",
        f"// `trustcbr run domains/experiments/benchmark-{scenario}.ron --out DIR`.",
        "(",
        "    seed: 2014,",
        f"    trials: {TRIALS[scenario]},",
        f"    max_commands: {MAX_COMMANDS},",
        "    adapter: (",
        "        thresholds: (trustworthy: 5.0, untrustworthy: -5.0),",
        "        lambda: 0.95,",
        "        retriever: inverted_index,",
        "        retention: any_search,",
        "        time_unit: task_seconds,",
        "    ),",
        "    arms: [",
        *[f"        \"{arm}\"," for arm in ARMS],
        "    ],",
        "    landscape_runs: 0,",
        "    benchmark: true,",
        "    experiments: [",
    ]
    for k in range(COUNT):
        folder = REPO / "domains/operators/benchmark" / scenario / f"eval-{k}"
        files = sorted(folder.glob("*.ron"))
        if not files:
            sys.exit(f"{folder}: no members (run `trustcbr population --scenario {scenario} "
                     f"--instance eval-{k} --out {folder.relative_to(REPO)}` first)")
        listed = ", ".join(f'"../operators/benchmark/{scenario}/eval-{k}/{f.name}"' for f in files)
        lines += [
            "        (",
            f"            scenario: \"{scenario}\",",
            "            operator: \"random\",",
            f"            population: Some((name: \"eval-{k}\")),",
            f"            operator_files: [{listed}],",
            "        ),",
        ]
    lines += ["    ],", ")", ""]
    return "\n".join(lines)


for scenario in ("movement", "patrol"):
    path = REPO / "domains/experiments" / f"benchmark-{scenario}.ron"
    path.write_text(suite(scenario))
    print(f"wrote {path.relative_to(REPO)}")
