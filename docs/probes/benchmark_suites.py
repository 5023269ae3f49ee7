#!/usr/bin/env python3
"""Writes domains/experiments/benchmark-{movement,patrol}.ron, every arm on the evaluation
instances eval-0 .. eval-(COUNT-1) of the prior (docs/simulation.md, "Operators no one
designed"), and domains/experiments/benchmark-dev-{movement,patrol}.ron, the same settings on
the development instances dev-0 .. dev-(COUNT-1). `trustcbr population` writes their members
to domains/operators/benchmark/SCENARIO/eval-K/ and domains/operators/benchmark-dev/SCENARIO/dev-K/
(run it first; docs/search-strategies.md, "The benchmark").

usage: docs/probes/benchmark_suites.py [COUNT]   (needs the Python package: pip install ./python)
         (default 20 instances of each split; trials
per scenario: TRIALS, chosen so that a suite runs within 10 minutes on the project's 2-core
machine)
"""

import pathlib
import sys

# Every built-in arm, as the strategies' registry lists them (the Python package reads it).
import trustcbr

REPO = pathlib.Path(__file__).resolve().parent.parent.parent
COUNT = int(sys.argv[1]) if __name__ == "__main__" and len(sys.argv) > 1 else 20
TRIALS = {"movement": 500, "patrol": 300}
# A trial's commands are capped (the trial is then truncated, counted as not settled): the
# paper's random walk needs thousands of commands a trial on a population with a small
# trustworthy region, and would alone exceed the suite's 10 minutes.
MAX_COMMANDS = 2000


# Per split (the prefix of its instances' names): the folder of their members under
# domains/operators, the suite's file name and what its header says the split is for.
SPLITS = {
    "eval": (
        "benchmark",
        "benchmark-{scenario}.ron",
        "the evaluation instances",
        "Nothing in any strategy was chosen on these instances.",
    ),
    "dev": (
        "benchmark-dev",
        "benchmark-dev-{scenario}.ron",
        "the development instances",
        "Strategies are developed on these instances, never judged.",
    ),
}


def opening(comment: list[str], scenario: str, arms: list[str]) -> list[str]:
    """A benchmark suite's lines up to its arms: `comment`, then the seed, the scenario's
    trials, the command cap and the paper's adapter (shared by docs/probes/stated_suites.py)."""
    return [
        *[f"// {line}" for line in comment],
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
        *[f'        "{arm}",' for arm in arms],
        "    ],",
        "    landscape_runs: 0,",
    ]


def suite(scenario: str, split: str) -> str:
    folder_name, file_name, which, promise = SPLITS[split]
    title = "benchmark" if split == "eval" else "development benchmark"
    comment = [
        f'The {title} for {scenario} (docs/search-strategies.md, "The benchmark"): every arm',
        f"on {which} {split}-0 .. {split}-{COUNT - 1} of the prior ugv-1, silent operators,",
        f"the paper's adapter. {promise} Written by",
        "docs/probes/benchmark_suites.py; run it with",
        f"`trustcbr run domains/experiments/{file_name.format(scenario=scenario)} --out DIR`.",
    ]
    lines = [
        *opening(comment, scenario, trustcbr.builtin_arms()),
        "    benchmark: true,",
        "    experiments: [",
    ]
    for k in range(COUNT):
        folder = REPO / "domains/operators" / folder_name / scenario / f"{split}-{k}"
        files = sorted(folder.glob("*.ron"))
        if not files:
            sys.exit(
                f"{folder}: no members (run `trustcbr population --scenario {scenario} "
                f"--instance {split}-{k} --out {folder.relative_to(REPO)}` first)"
            )
        listed = ", ".join(
            f'"../operators/{folder_name}/{scenario}/{split}-{k}/{f.name}"' for f in files
        )
        lines += [
            "        (",
            f'            scenario: "{scenario}",',
            '            operator: "random",',
            f'            population: Some((name: "{split}-{k}")),',
            f"            operator_files: [{listed}],",
            "        ),",
        ]
    lines += ["    ],", ")", ""]
    return "\n".join(lines)


if __name__ == "__main__":
    for split, (_, file_name, _, _) in SPLITS.items():
        for scenario in ("movement", "patrol"):
            path = REPO / "domains/experiments" / file_name.format(scenario=scenario)
            path.write_text(suite(scenario, split))
            print(f"wrote {path.relative_to(REPO)}")
