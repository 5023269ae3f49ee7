"""Arms told the robot's context against their context-blind twins, on the same trials.

Reads a report's ``trials.jsonl`` from a suite whose experiments run in contexts and whose
arms include ``X`` and ``X+context-blind`` (domains/experiments/contexts.ron), pairs each
trial of ``X`` with the same trial of its twin, and prints per experiment, arm and context
(and over all contexts) the behaviors evaluated and untrustworthy commands per trial of
each, the paired difference (told minus blind) and its Wilcoxon signed-rank p (normal
approximation, as docs/probes/paired_populations.py). Used for docs/simulation.md,
"Context-aware cases against context-blind ones":

    trustcbr run domains/experiments/contexts.ron --out DIR
    python3 docs/probes/context_pairs.py DIR/trials.jsonl
"""

from __future__ import annotations

import json
import statistics
import sys
from pathlib import Path
from typing import Dict, List, Tuple

sys.path.insert(0, str(Path(__file__).resolve().parent))
from paired_populations import wilcoxon_p  # noqa: E402

BLIND = "+context-blind"
# The suffixes written after it (lab::NameOptions: NAME+context-blind+learned-start+competent).
LATER = ("+learned-start", "+competent")


def blind_twin(arm: str) -> str:
    """The name of `arm` blind to the context: its suffix goes before the later ones."""
    later = ""
    for suffix in reversed(LATER):
        if arm.endswith(suffix):
            arm, later = arm[: -len(suffix)], suffix + later
    return arm + BLIND + later


# (experiment, arm, trial) -> (context, behaviors, untrustworthy commands)
Trials = Dict[Tuple[str, str, int], Tuple[str, int, int]]


def read(path: Path) -> Trials:
    trials: Trials = {}
    for line in path.read_text().splitlines():
        row = json.loads(line)
        context = ",".join(f"{k}={v}" for k, v in sorted(row.get("context", {}).items()))
        trials[(row["experiment"], row["arm"], row["trial"])] = (
            context or "default",
            row["behaviors_evaluated"],
            row["untrustworthy"],
        )
    return trials


def mean_ci(values: List[int]) -> str:
    mean = statistics.fmean(values)
    half = 1.96 * statistics.stdev(values) / len(values) ** 0.5 if len(values) > 1 else 0.0
    return f"{mean:.2f} ± {half:.2f}"


def row(label: str, pairs: List[Tuple[Tuple[int, int], Tuple[int, int]]]) -> str:
    cells = [label, str(len(pairs))]
    for k in (0, 1):
        told = [p[0][k] for p in pairs]
        blind = [p[1][k] for p in pairs]
        differences = [float(t - b) for t, b in zip(told, blind)]
        cells += [
            mean_ci(told),
            mean_ci(blind),
            f"{statistics.fmean(differences):+.2f}",
            f"{wilcoxon_p(differences):.2g}",
        ]
    return "| " + " | ".join(cells) + " |"


def main() -> None:
    trials = read(Path(sys.argv[1]))
    print(
        "| experiment / arm / context | trials | behaviors, told | behaviors, blind | "
        "difference | p | untrustworthy, told | untrustworthy, blind | difference | p |"
    )
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    arms = {(e, a) for (e, a, _) in trials}
    twins = sorted((e, a) for (e, a) in arms if (e, blind_twin(a)) in arms)
    for experiment, arm in twins:
        by_context: Dict[str, List[Tuple[Tuple[int, int], Tuple[int, int]]]] = {}
        for (e, a, trial), (context, behaviors, untrustworthy) in trials.items():
            if (e, a) != (experiment, arm):
                continue
            _, twin_behaviors, twin_untrustworthy = trials[(e, blind_twin(a), trial)]
            by_context.setdefault(context, []).append(
                ((behaviors, untrustworthy), (twin_behaviors, twin_untrustworthy))
            )
        everything = [p for pairs in by_context.values() for p in pairs]
        print(row(f"{experiment} / {arm} / all", everything))
        for context, pairs in sorted(by_context.items()):
            print(row(f"{experiment} / {arm} / {context}", pairs))


if __name__ == "__main__":
    main()
