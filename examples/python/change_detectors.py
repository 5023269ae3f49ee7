"""The mission change detector beside river's ADWIN and Page-Hinkley, on the same streams.

A *stream* is one watched behavior's commands on a mission: a behavior the first
operator trusts is begun, the first operator's outcomes (``trustcbr.simulate``) run until
the adapter settles on it, then go on for ``--before`` commands; in a stream *with a
change* another operator, who finds the behavior untrustworthy, takes over unannounced
for ``--after`` commands; in a stream *without* the first operator goes on instead.
Every detector reads the same outcomes (1: failed or interrupted, 0: completed):

- ``thresholds``: the paper's watch alone (``Adapter(..., mission=True)``): the behavior
  is given up when its capped estimate falls to the untrustworthy threshold;
- ``cusum``: the same with the change detector (``detect_changes=True``,
  docs/missions.md, *A change detector*);
- ``adwin`` and ``page-hinkley``: river's ``drift.ADWIN()`` and
  ``drift.PageHinkley(mode="up")`` with their default settings, fed the watched commands
  (the settling episode's too, as the CUSUM's record has them; an alarm counts once the
  behavior settled).

For each detector it prints the share of streams with a change in which it raised before
the stream's end, the median commands from the change to its alarm, the untrustworthy
commands until then, and the share of streams without a change in which it raised at all
(a false alarm). Usage::

    pip install ./python river
    python examples/python/change_detectors.py --streams 100
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from river import drift

import trustcbr

ROOT = Path(__file__).resolve().parents[2]
OPERATORS = ROOT / "domains" / "operators" / "ladder"
DETECTORS = ["thresholds", "cusum", "adwin", "page-hinkley"]


@dataclass
class Tally:
    """What one detector did over the streams."""

    detected: int = 0
    delays: list[int] = field(default_factory=list)
    untrustworthy: list[int] = field(default_factory=list)
    false_alarms: int = 0


def trusted_and_not(
    scenario: str, first: str, second: str, runs: int
) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """Behaviors the first operator lets complete at least 90% of their runs, split into
    those the second lets complete at most half (a change needs adaptation) and the rest."""
    a = trustcbr.landscape(scenario, first, runs=runs, seed=1, progress=False)
    b = trustcbr.landscape(scenario, second, runs=runs, seed=2, progress=False)
    changed: list[dict[str, Any]] = []
    kept: list[dict[str, Any]] = []
    for index in np.ndindex(a.p_complete.shape):
        if a.p_complete[index] < 0.9:
            continue
        behavior = {name: a.values[k][i] for k, (name, i) in enumerate(zip(a.components, index))}
        (changed if b.p_complete[index] <= 0.5 else kept).append(behavior)
    return changed, kept


def stream(
    scenario: str,
    behavior: dict[str, Any],
    operators: tuple[str, str],
    change: bool,
    seed: int,
    lengths: tuple[int, int],
) -> dict[str, Tally] | None:
    """Runs one stream through every detector; `None` when the first operator never lets
    the adapters settle on the behavior."""
    cases = tempfile.TemporaryDirectory()
    watchers = {
        "thresholds": trustcbr.Adapter(
            scenario, Path(cases.name) / "a.db", seed=seed, mission=True
        ),
        "cusum": trustcbr.Adapter(
            scenario, Path(cases.name) / "b.db", seed=seed, mission=True, detect_changes=True
        ),
    }
    rivers = {"adwin": drift.ADWIN(), "page-hinkley": drift.PageHinkley(mode="up")}
    for adapter in watchers.values():
        adapter.begin(behavior)
    alarms: dict[str, int] = {}
    settled_at = None
    command = 0
    bad_at: list[bool] = []
    while True:
        before, after = lengths
        if settled_at is not None and command >= settled_at + before + after:
            break
        late = settled_at is not None and command >= settled_at + before
        operator = operators[1] if change and late else operators[0]
        outcome = trustcbr.simulate(scenario, behavior, operator, seed=seed * 100_000 + command)
        bad = outcome["outcome"] != "completed"
        bad_at.append(bad)
        for name, adapter in watchers.items():
            if name in alarms:
                continue
            kind = adapter.tell_outcome(outcome).kind
            if settled_at is None and kind == "switch":
                return None
            if kind == "settled":
                settled_at = command + 1
            elif settled_at is not None and kind == "switch":
                alarms[name] = command
        for name, detector in rivers.items():
            detector.update(int(bad))
            if settled_at is not None and name not in alarms and detector.drift_detected:
                alarms[name] = command
        command += 1
        if settled_at is None and command > 2_000:
            return None
    cases.cleanup()
    assert settled_at is not None
    change_at = settled_at + lengths[0]
    tallies = {name: Tally() for name in DETECTORS}
    for name, at in alarms.items():
        if change and at >= change_at:
            tallies[name].detected = 1
            tallies[name].delays.append(at - change_at + 1)
            tallies[name].untrustworthy.append(sum(bad_at[change_at : at + 1]))
        else:
            tallies[name].false_alarms = 1
    return tallies


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenario", default="movement")
    parser.add_argument("--rung", default="rung-2")
    parser.add_argument("--streams", type=int, default=100)
    parser.add_argument("--before", type=int, default=150)
    parser.add_argument("--after", type=int, default=150)
    parser.add_argument("--landscape-runs", type=int, default=50)
    args = parser.parse_args()
    folder = OPERATORS / args.scenario / args.rung
    first, second = (str(folder / f"{name}.ron") for name in ("dispatcher", "supervisor"))
    changed, kept = trusted_and_not(args.scenario, first, second, args.landscape_runs)
    print(f"{len(changed)} behaviors need adaptation at the change, {len(kept)} do not")
    for change, pool in ((True, changed), (False, kept)):
        totals = {name: Tally() for name in DETECTORS}
        runs = 0
        seed = 0
        while runs < args.streams and pool:
            seed += 1
            behavior = pool[seed % len(pool)]
            tallies = stream(
                args.scenario, behavior, (first, second), change, seed, (args.before, args.after)
            )
            if tallies is None:
                continue
            runs += 1
            for name, tally in tallies.items():
                total = totals[name]
                total.detected += tally.detected
                total.delays += tally.delays
                total.untrustworthy += tally.untrustworthy
                total.false_alarms += tally.false_alarms
        print(f"\nstreams {'with' if change else 'without'} a change: {runs}")
        for name, total in totals.items():
            if change:
                median = statistics.median(total.delays) if total.delays else float("nan")
                paid = statistics.mean(total.untrustworthy) if total.untrustworthy else float("nan")
                print(
                    f"  {name:13} detected {total.detected}/{runs}, median delay {median:.0f}, "
                    f"untrustworthy until then {paid:.1f} (mean), "
                    f"false alarms before the change {total.false_alarms}"
                )
            else:
                print(f"  {name:13} false alarms {total.false_alarms}/{runs}")


if __name__ == "__main__":
    main()
