#!/usr/bin/env python3
"""Compares two runs of the default reproduce and the committed mission suites, before and
after a change that must not move any result (docs/probes/same_results.sh runs them).

usage: docs/probes/same_results.py BEFORE AFTER

Each folder holds `reproduce/` (`trustcbr reproduce --out`) and one folder per mission suite
(`trustcbr run docs/results/NAME/config.ron --out`). The records must be byte-identical:
`trials.jsonl`, every `missions.jsonl`, `table.md` and `missions.md`; `summary.json` must be
equal but for what says when and how the run was made (`elapsed_s`, `provenance`, `threads`).
Every other file (the figures, the page) is compared too and reported, not required.
Prints one line per file and exits 1 if a record differs.
"""

import json
import sys
from pathlib import Path
from typing import Any

RECORDS = {"trials.jsonl", "missions.jsonl", "table.md", "missions.md"}
# What a summary says of the run rather than of its results.
OF_THE_RUN = {"elapsed_s", "provenance", "threads"}


def without_run(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: without_run(v) for k, v in value.items() if k not in OF_THE_RUN}
    if isinstance(value, list):
        return [without_run(v) for v in value]
    return value


def main() -> int:
    before, after = Path(sys.argv[1]), Path(sys.argv[2])
    failed = False
    for old in sorted(p for p in before.rglob("*") if p.is_file()):
        rel = old.relative_to(before)
        if rel.suffix == ".log" or rel.name == "times":
            continue
        new = after / rel
        if not new.is_file():
            print(f"MISSING {rel}")
            failed = failed or rel.name in RECORDS or rel.name == "summary.json"
            continue
        if old.read_bytes() == new.read_bytes():
            verdict = "identical"
        elif rel.name == "summary.json" and without_run(json.loads(old.read_text())) == without_run(
            json.loads(new.read_text())
        ):
            verdict = "identical but for the run's own fields"
        else:
            verdict = "DIFFERS"
            failed = failed or rel.name in RECORDS or rel.name == "summary.json"
        print(f"{verdict:40} {rel}")
    print("records identical" if not failed else "RECORDS DIFFER")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
