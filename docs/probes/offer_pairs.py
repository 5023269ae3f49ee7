"""An answered overtrust alert that offers a safer behavior, against one that only asks the
operator to look afresh, on the same missions.

Runs a mission suite whose plans set ``offer_safer: true`` and its twin without it (the
same text with that setting removed: the same plans at the same places, so the same
missions, courses and streams), then pairs the two reports' answered missions by plan,
arm and mission, and prints per plan and arm the harm per mission and untrustworthy
commands per mission of each, the paired difference in harm and its Wilcoxon
signed-rank p (normal approximation, as docs/probes/paired_populations.py). Used for
docs/missions.md, "The safer behavior an answered alert offers":

    python3 docs/probes/offer_pairs.py domains/experiments/missions-offer.ron

The binary is ``$TRUSTCBR_BIN`` or ``target/release/trustcbr``.
"""

from __future__ import annotations

import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Dict, List, Tuple

sys.path.insert(0, str(Path(__file__).resolve().parent))
from paired_populations import wilcoxon_p  # noqa: E402

Key = Tuple[str, str, int]


def answered_missions(report: Path) -> Dict[Key, Tuple[int, int]]:
    """(plan, arm, mission) -> (harm, untrustworthy commands), answered missions only."""
    out: Dict[Key, Tuple[int, int]] = {}
    for line in (report / "missions.jsonl").read_text().splitlines():
        row = json.loads(line)
        if row["answers_alerts"]:
            record = row["record"]
            out[(row["plan"], row["arm"], record["mission"])] = (
                row["harm"],
                record["untrustworthy"],
            )
    return out


def run(binary: str, suite: Path, out: Path) -> None:
    subprocess.run(
        [binary, "run", str(suite), "--out", str(out)],
        check=True,
        stdout=subprocess.DEVNULL,
    )


def mean_ci(values: List[float]) -> str:
    mean = statistics.fmean(values)
    half = 1.96 * statistics.stdev(values) / len(values) ** 0.5 if len(values) > 1 else 0.0
    return f"{mean:.2f} ± {half:.2f}"


def main() -> None:
    suite = Path(sys.argv[1])
    binary = os.environ.get("TRUSTCBR_BIN", "target/release/trustcbr")
    text = suite.read_text()
    if ", offer_safer: true" not in text:
        sys.exit(f"{suite}: no plan's competence sets `, offer_safer: true`")
    with tempfile.TemporaryDirectory() as scratch:
        folder = Path(scratch)
        twin = folder / "twin.ron"
        twin.write_text(text.replace(", offer_safer: true", ""))
        run(binary, suite, folder / "offered")
        run(binary, twin, folder / "attention")
        offered = answered_missions(folder / "offered")
        attention = answered_missions(folder / "attention")
    pairs: Dict[Tuple[str, str], List[Tuple[Tuple[int, int], Tuple[int, int]]]] = {}
    for key, with_offer in offered.items():
        pairs.setdefault(key[:2], []).append((attention[key], with_offer))
    print(
        "| plan | arm | harm, attention only | harm, safer offered | paired difference | "
        "Wilcoxon p | untrustworthy, attention only | untrustworthy, safer offered |"
    )
    print("|---|---|---:|---:|---:|---:|---:|---:|")
    for (plan, arm), missions in pairs.items():
        before = [float(a[0]) for a, _ in missions]
        after = [float(o[0]) for _, o in missions]
        differences = [a - o for a, o in zip(before, after)]
        print(
            f"| {plan} | {arm} | {mean_ci(before)} | {mean_ci(after)} | "
            f"{mean_ci(differences)} | {wilcoxon_p(differences):.2g} | "
            f"{mean_ci([float(a[1]) for a, _ in missions])} | "
            f"{mean_ci([float(o[1]) for _, o in missions])} |"
        )


if __name__ == "__main__":
    main()
