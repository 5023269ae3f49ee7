#!/usr/bin/env python3
"""The operator prior's instances, described: for the first COUNT development instances of
each scenario, `trustcbr population` writes the members twice, screened and unscreened;
`trustcbr landscape` (every component fixed: one row per behavior) estimates each member's
trustworthy region (ladder.py's `region`: positive mean weighted outcome per command), with
a seed no instance uses (so no screen's runs are reused). Per instance: the members' region
sizes, how many behaviors every member trusts, and whether a member trusts none (the
instance is degenerate). The numbers describe the generated instances; nothing is tuned
on them.

usage: docs/probes/prior.py [TRUSTCBR] [OUT_DIR] [COUNT]   (runs: movement 400, patrol 40)
"""
import hashlib
import pathlib
import re
import subprocess
import sys

from ladder import region

BIN = sys.argv[1] if len(sys.argv) > 1 else "target/release/trustcbr"
OUT = pathlib.Path(sys.argv[2] if len(sys.argv) > 2 else "/tmp/prior")
COUNT = int(sys.argv[3]) if len(sys.argv) > 3 else 20
RUNS = {"movement": 400, "patrol": 40}
# Outside the development and evaluation seed ranges: independent of every screen.
SEED = 2_000_000_000


def population(scenario, instance, screened):
    out = OUT / scenario / (instance if screened else f"{instance}-unscreened")
    if not out.exists():
        subprocess.run(
            [BIN, "population", "--scenario", scenario, "--instance", instance,
             "--out", str(out)] + ([] if screened else ["--unscreened"]),
            check=True, stdout=subprocess.DEVNULL)
    return sorted(out.glob("*.ron"))


def trusted(scenario, path):
    """The member's region; members equal but for their header share one landscape."""
    body = "".join(line for line in path.read_text().splitlines(True)
                   if not line.startswith("//"))
    key = hashlib.sha256(body.encode()).hexdigest()[:16]
    out = OUT / "landscapes" / scenario / key
    if not (out / "landscape.csv").exists():
        subprocess.run(
            [BIN, "landscape", "--scenario", scenario, "--operator", str(path),
             "--runs", str(RUNS[scenario]), "--seed", str(SEED), "--out", str(out)],
            check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return region(scenario, out / "landscape.csv")


def draw(path):
    found = re.search(r"its stream's draw (\d+)", path.read_text())
    return int(found.group(1)) if found else 1


def main():
    print("| scenario | instance | members | draws | trustworthy behaviors per member | "
          "trusted by all | unscreened: members trusting nothing |")
    print("| --- | --- | --- | --- | --- | --- | --- |")
    totals = {}
    for scenario in ["movement", "patrol"]:
        t = totals[scenario] = dict(instances=0, members=0, refused=0, degenerate=0,
                                    empty_members=0, screened_degenerate=0,
                                    screened_empty=0, shared_none=0)
        for k in range(COUNT):
            instance = f"dev-{k}"
            screened = population(scenario, instance, True)
            unscreened = population(scenario, instance, False)
            regions = [trusted(scenario, p) for p in screened]
            raw = [trusted(scenario, p) for p in unscreened]
            draws = [draw(p) for p in screened]
            everyone = set.intersection(*regions)
            empty_raw = sum(1 for r in raw if not r)
            t["instances"] += 1
            t["members"] += len(screened)
            t["refused"] += sum(1 for d in draws if d > 1)
            t["degenerate"] += empty_raw > 0
            t["empty_members"] += empty_raw
            t["screened_empty"] += sum(1 for r in regions if not r)
            t["screened_degenerate"] += any(not r for r in regions)
            t["shared_none"] += not everyone
            print(f"| {scenario} | {instance} | {len(screened)} | "
                  f"{', '.join(map(str, draws))} | "
                  f"{', '.join(str(len(r)) for r in regions)} | {len(everyone)} | "
                  f"{empty_raw} |")
    print()
    for scenario, t in totals.items():
        print(f"{scenario}: {t['instances']} instances, {t['members']} members; "
              f"screen refused {t['refused']} first draws; unscreened: "
              f"{t['empty_members']} members trust nothing, {t['degenerate']} instances "
              f"degenerate; screened: {t['screened_empty']} members trust nothing, "
              f"{t['screened_degenerate']} instances degenerate; "
              f"{t['shared_none']} instances with no behavior every member trusts")


if __name__ == "__main__":
    main()
