#!/usr/bin/env python3
"""Whether demanding operators' small trustworthy regions lie inside other members' (the
reason for the `nested` search, docs/search-strategies.md). For every member of patrol's
development populations that trusts at most SMALL behaviors: how many of its trusted
behaviors other members of its population trust too, its distance (component changes) to
the nearest behavior another member trusts, and how soon a search meets its region when
it visits behaviors by their distance from three behaviors drawn from each other member's
region (nearest first, in a random order within a distance; median over 200 draws), beside
uniform sampling's expected 16,000 / (region + 1). Landscapes by `trustcbr landscape`, 40
runs per behavior, seed 2,000,000,000 (no instance uses it); nothing here is tuned.

usage: docs/probes/nested_regions.py [TRUSTCBR] [OUT_DIR]
"""
import csv
import pathlib
import random
import subprocess
import sys

from ladder import region

BIN = sys.argv[1] if len(sys.argv) > 1 else "target/release/trustcbr"
OUT = pathlib.Path(sys.argv[2] if len(sys.argv) > 2 else "/tmp/nested-regions")
MEMBERS = pathlib.Path(__file__).resolve().parents[2] / "domains/operators/benchmark-dev/patrol"
SEED = 2_000_000_000
SMALL = 50
COMPONENTS = 4
DRAWS = 200
KNOWN = 3


def landscape(path):
    out = OUT / path.parent.name / path.stem
    if not (out / "landscape.csv").exists():
        subprocess.run(
            [BIN, "landscape", "--scenario", "patrol", "--operator", str(path),
             "--runs", "40", "--seed", str(SEED), "--out", str(out)],
            check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return out / "landscape.csv"


def value_indices(csv_path):
    """Each component's values in order, from a landscape's rows."""
    with open(csv_path) as f:
        rows = [row for row in csv.reader(f) if len(row) > COMPONENTS][1:]
    return [sorted({float(row[k]) for row in rows}) for k in range(COMPONENTS)]


def neighbours(b, sizes):
    for k in range(COMPONENTS):
        for step in (-1, 1):
            v = b[k] + step
            if 0 <= v < sizes[k]:
                yield b[:k] + (v,) + b[k + 1:]


def first_met(target, seeds, sizes, rng):
    """How many behaviors a search visits, nearest to `seeds` first, until it meets
    `target`; with the distance it met it at."""
    seen = set(seeds)
    layer = list(seeds)
    visited = 0
    distance = 0
    while layer:
        rng.shuffle(layer)
        for b in layer:
            visited += 1
            if b in target:
                return visited, distance
        following = []
        for b in layer:
            for n in neighbours(b, sizes):
                if n not in seen:
                    seen.add(n)
                    following.append(n)
        layer = following
        distance += 1
    return None, None


def main():
    print("| member | trusted | also trusted by another member | changes to another's region | "
          "met after (median) | uniform |")
    print("| --- | ---: | ---: | ---: | ---: | ---: |")
    for folder in sorted(MEMBERS.iterdir(), key=lambda p: int(p.name.split("-")[1])):
        files = sorted(folder.glob("*.ron"))
        paths = [landscape(f) for f in files]
        values = value_indices(paths[0])
        sizes = [len(v) for v in values]

        def index(b):
            return tuple(values[k].index(float(b[k])) for k in range(COMPONENTS))

        regions = [{index(b) for b in region("patrol", p)} for p in paths]
        for m, own in enumerate(regions):
            if not own or len(own) > SMALL:
                continue
            others = [r for j, r in enumerate(regions) if j != m and r]
            union = set().union(*others)
            changes = min(sum(abs(a - c) for a, c in zip(b, o)) for b in own for o in union)
            met = []
            for draw in range(DRAWS):
                rng = random.Random(draw)
                seeds = set()
                for r in others:
                    seeds |= set(rng.sample(sorted(r), min(KNOWN, len(r))))
                met.append(first_met(own, seeds, sizes, rng)[0])
            met.sort()
            uniform = 16_000 // (len(own) + 1)
            print(f"| {files[m].stem} | {len(own)} | {len(own & union)} | {changes} | "
                  f"{met[DRAWS // 2]} | {uniform} |")


if __name__ == "__main__":
    main()
