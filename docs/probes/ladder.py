#!/usr/bin/env python3
"""The conflict ladder, measured: for every rung of domains/operators/ladder/<scenario>/,
the landscape of each of its operators (`trustcbr landscape`, every component fixed: one
row per behavior), and per rung the share of behaviors trustworthy for every operator,
the pairwise Jaccard index of the trustworthy regions (and the overlap coefficient,
|A & B| / min(|A|, |B|): 1 when one region is nested in the other), and whether one behavior pleases
everyone.

A behavior is trustworthy for an operator when its mean weighted outcome per command is
positive (trust/src/experiment/landscape.rs, `trusted_on_average`): completions count
+w_completed, every failure or interruption -w_cause. The ladder's operators use the
paper's weights: all 1 in movement; in patrol 1/3, a detonation 1.

usage: docs/probes/ladder.py [TRUSTCBR] [OUT_DIR]   (runs: movement 400, patrol 40)
"""
import csv
from fractions import Fraction
import itertools
import pathlib
import subprocess
import sys

BIN = sys.argv[1] if len(sys.argv) > 1 else "target/release/trustcbr"
OUT = pathlib.Path(sys.argv[2] if len(sys.argv) > 2 else "/tmp/ladder")
RUNS = {"movement": 400, "patrol": 40}
WEIGHTS = {  # completed, default, by cause
    "movement": (1, 1, {}),
    "patrol": (Fraction(1, 3), Fraction(1, 3), {"detonation": 1}),
}
COMPONENTS = {"movement": 2, "patrol": 4}


def region(scenario, csv_path):
    """The trustworthy region of the landscape in `csv_path` (every component fixed): the
    behaviors whose mean weighted outcome per command is positive, as tuples of values."""
    completed_w, default_w, by_cause = WEIGHTS[scenario]
    found = set()
    with open(csv_path) as f:
        rows = csv.reader(f)
        header = next(rows)
        k = COMPONENTS[scenario]
        causes = header[k + 3:]
        for row in rows:
            runs, done = int(row[k]), int(row[k + 1])
            drift = completed_w * done
            for cause, n in zip(causes, row[k + 3:]):
                drift -= by_cause.get(cause, default_w) * int(n)
            # Exact arithmetic: a drift of exactly 0 (as many completions as other
            # outcomes at equal weights) is not trustworthy, whatever the rounding.
            if drift > 0:
                found.add(tuple(row[:k]))
    return found


def trusted(scenario, path):
    out = OUT / scenario / path.parent.name / path.stem
    if not (out / "landscape.csv").exists():
        subprocess.run(
            [BIN, "landscape", "--scenario", scenario, "--operator", str(path),
             "--runs", str(RUNS[scenario]), "--out", str(out)],
            check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return region(scenario, out / "landscape.csv")


def main():
    root = pathlib.Path("domains/operators/ladder")
    print("| scenario | rung | operators | trusted by each | trusted by all (share) | pairwise Jaccard (overlap) | one pleases all |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for scenario in ["movement", "patrol"]:
        size = {"movement": 400, "patrol": 16000}[scenario]
        for rung in sorted((root / scenario).iterdir()):
            files = sorted(rung.glob("*.ron"))
            regions = {p.stem: trusted(scenario, p) for p in files}
            everyone = set.intersection(*regions.values())
            jaccard = []
            for a, b in itertools.combinations(regions, 2):
                union = regions[a] | regions[b]
                j = len(regions[a] & regions[b]) / len(union) if union else 1.0
                smaller = min(len(regions[a]), len(regions[b]))
                o = len(regions[a] & regions[b]) / smaller if smaller else 1.0
                jaccard.append(f"{a}/{b} {j:.2f} (overlap {o:.2f})")
            each = ", ".join(f"{n} {len(r)}" for n, r in regions.items())
            print(f"| {scenario} | {rung.name} | {len(files)} | {each} | "
                  f"{len(everyone)} ({len(everyone) / size:.3f}) | {'; '.join(jaccard)} | "
                  f"{'yes' if everyone else 'no'} |")


if __name__ == "__main__":
    main()
