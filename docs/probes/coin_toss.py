"""What a behavior that completes about half its commands costs, and where trials pay it.

Two figures for docs/search-strategies.md ("Is a coin toss given up early?"):

1. Exactly, from the paper's estimate: a behavior that completes each command with
   probability ``p`` moves the estimate by one step of ``1/3`` up or down (the default
   patrol and movement weights; thresholds at +-5, so 15 steps each way). The gambler's
   ruin gives the probability it is trusted, the expected commands until it is judged and,
   by Wald's identity, the expected untrustworthy commands among them (``(1 - p)`` of the
   commands).
2. Wald's approximations for the sequential probability ratio test that would give such a
   behavior up early: telling ``p = 0.5`` from ``p = 0.6`` with 5% errors each way, the
   expected commands until it decides under each (``ln((1 - b) / a)`` over the expected
   log-likelihood ratio per command, times the chance of deciding that way), and the
   untrustworthy commands among them.
3. From a suite report's ``trials.jsonl``: the share of an arm's trials whose commands
   exceed 15 per evaluated behavior by 100 or more (a walk that lingered), and the share
   of the arm's untrustworthy commands those trials carry:

    python3 docs/probes/coin_toss.py [REPORT/trials.jsonl ARM ...]
"""

from __future__ import annotations

import json
import math
import sys

STEPS = 15
"""Steps of 1/3 from 0 to either threshold (+-5)."""

LINGERED = 100
"""Commands beyond 15 per evaluated behavior that mark a trial whose walk lingered."""


def walk(p: float, steps: int = STEPS) -> tuple[float, float, float]:
    """(P(trusted), E[commands], E[untrustworthy commands]) from 0, thresholds at +-steps."""
    n = 2 * steps
    q = 1.0 - p
    if abs(p - q) < 1e-12:
        trusted = 0.5
        commands = float(steps * steps)
    else:
        r = q / p
        trusted = (1.0 - r**steps) / (1.0 - r**n)
        commands = (steps - n * trusted) / (q - p)
    return trusted, commands, q * commands


def sprt(p0: float, p1: float, alpha: float, beta: float) -> tuple[float, float]:
    """Wald's expected sample sizes of the SPRT of ``p0`` (trustworthy enough) against
    ``p1`` (a coin toss), under ``p1`` and under ``p0``."""
    upper = math.log((1.0 - beta) / alpha)  # accept p1: give the behavior up
    lower = math.log(beta / (1.0 - alpha))  # accept p0: keep it

    def drift(p: float) -> float:
        return p * math.log(p1 / p0) + (1.0 - p) * math.log((1.0 - p1) / (1.0 - p0))

    under_p1 = ((1.0 - beta) * upper + beta * lower) / drift(p1)
    under_p0 = (alpha * upper + (1.0 - alpha) * lower) / drift(p0)
    return under_p1, under_p0


def lingering(path: str, arms: list[str]) -> dict[str, tuple[int, float, float]]:
    """Per arm: trials, share of them that lingered, share of untrustworthy commands."""
    with open(path, encoding="utf-8") as lines:
        rows = [json.loads(line) for line in lines]
    out: dict[str, tuple[int, float, float]] = {}
    for arm in arms:
        trials = [r for r in rows if r["arm"] == arm]
        total = sum(r["untrustworthy"] for r in trials)
        slow = [
            r
            for r in trials
            if r["commands"] - 15 * r["behaviors_evaluated"] >= LINGERED
        ]
        share = sum(r["untrustworthy"] for r in slow) / total if total else 0.0
        out[arm] = (len(trials), len(slow) / len(trials) if trials else 0.0, share)
    return out


def main() -> None:
    print("p      P(trusted)  E[commands]  E[untrustworthy]  untrustworthy per trusted")
    for p in [0.5, 0.55, 0.6, 0.7, 0.8, 0.9, 0.95]:
        trusted, commands, untrustworthy = walk(p)
        print(
            f"{p:<6} {trusted:<11.3f} {commands:<12.1f} {untrustworthy:<17.1f} "
            f"{untrustworthy / trusted:.1f}"
        )
    coin, fair = sprt(0.6, 0.5, 0.05, 0.05)
    print(
        f"SPRT 0.6 against 0.5, 5% errors: {coin:.0f} commands ({coin / 2:.0f} untrustworthy) "
        f"to give up a coin toss; {fair:.0f} commands to clear a 0.6 behavior"
    )
    if len(sys.argv) > 2:
        for arm, (n, slow, share) in lingering(sys.argv[1], sys.argv[2:]).items():
            print(
                f"{arm}: {n} trials, {slow:.1%} lingered, {share:.1%} of untrustworthy commands"
            )


if __name__ == "__main__":
    main()
