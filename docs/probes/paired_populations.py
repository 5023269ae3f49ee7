"""Population by population, one arm against others on a suite report's trials.

For each experiment (population) of a report's ``trials.jsonl`` and each other arm, a
Wilcoxon signed-rank test (normal approximation, zero differences dropped, ties given
mean ranks) on the paired trials' untrustworthy commands; a population is a win for the
first arm when its mean is lower and p < 0.05, a loss when higher, else a tie. Used for
docs/peers.md, "The benchmark's evaluation populations":

    python3 docs/probes/paired_populations.py REPORT/trials.jsonl tpe-warm conditioned uniform
"""

from __future__ import annotations

import json
import math
import sys
from collections import defaultdict
from typing import Dict, List, Tuple


def wilcoxon_p(differences: List[float]) -> float:
    """Two-sided p of the signed-rank test, normal approximation with tie correction."""
    d = [x for x in differences if x != 0]
    n = len(d)
    if n == 0:
        return 1.0
    order = sorted(range(n), key=lambda i: abs(d[i]))
    ranks = [0.0] * n
    ties = 0.0
    i = 0
    while i < n:
        j = i
        while j + 1 < n and abs(d[order[j + 1]]) == abs(d[order[i]]):
            j += 1
        rank = (i + j) / 2 + 1
        for k in range(i, j + 1):
            ranks[order[k]] = rank
        t = j - i + 1
        ties += t**3 - t
        i = j + 1
    w_plus = sum(r for r, x in zip(ranks, d) if x > 0)
    mean = n * (n + 1) / 4
    var = n * (n + 1) * (2 * n + 1) / 24 - ties / 48
    if var <= 0:
        return 1.0
    z = (w_plus - mean) / math.sqrt(var)
    return math.erfc(abs(z) / math.sqrt(2))


def main() -> None:
    path, first, *others = sys.argv[1:]
    runs: Dict[Tuple[str, str], Dict[int, int]] = defaultdict(dict)
    with open(path) as lines:
        for line in lines:
            t = json.loads(line)
            runs[(t["experiment"], t["arm"])][t["trial"]] = t["untrustworthy"]
    experiments = sorted({e for e, _ in runs}, key=lambda e: (len(e), e))
    for other in others:
        wins: List[str] = []
        ties: List[str] = []
        losses: List[str] = []
        for e in experiments:
            a, b = runs[(e, first)], runs[(e, other)]
            trials = sorted(a.keys() & b.keys())
            diff = [float(a[t] - b[t]) for t in trials]
            p = wilcoxon_p(diff)
            mean = sum(diff) / len(diff)
            name = e.split("/")[-1]
            (wins if p < 0.05 and mean < 0 else losses if p < 0.05 else ties).append(name)
        print(f"{first} vs {other}: {len(wins)}/{len(ties)}/{len(losses)}")
        print(f"  wins: {', '.join(wins) or '-'}; losses: {', '.join(losses) or '-'}")


if __name__ == "__main__":
    main()
