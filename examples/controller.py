#!/usr/bin/env python3
"""A robot controller that drives `trustcbr serve` the way a real one would.

Python standard library only. The controller owns a small simulated world: a wheeled
robot crossing a 30 m route past obstacles for an operator who interrupts when the robot
is too slow (a 15 s deadline), bumps into things (too little padding, or too fast to
stop), or gets stuck (so much padding that no gap is wide enough). After every command it
reports the outcome to the adapter and applies the behavior the reply names.

By default it runs episodes, one per operator (the paper's episode mode). With --mission
it runs one long mission (`serve --mission`): after the robot settles it keeps reporting
outcomes, the world changes without telling the robot (another operator takes over who
wants the robot faster, or slower near people, than the behavior in use; then the route
gets crowded while the operator, trusting the robot, stops reacting to its bumps), and
the controller follows the server's re-adaptations and answers its alerts by asking the
operator to supervise.

    python3 examples/controller.py --cases cases.db
    python3 examples/controller.py --cases cases.db --mission
    python3 examples/controller.py --server target/debug/trustcbr --cases cases.db
    trustcbr serve --domain movement --cases cases.db --listen 127.0.0.1:7878 &
    python3 examples/controller.py --connect 127.0.0.1:7878
    (a mission over TCP needs `serve ... --mission`, and --mission here)

Without --server, the binary is the one named by the TRUSTCBR environment variable, else
`trustcbr` on PATH (`cargo install --path .` puts it there), else the newest of
target/release/trustcbr and target/debug/trustcbr in this repository (`cargo build`).

The protocol is documented in docs/protocol.md.
"""

import argparse
import json
import os
import random
import shutil
import socket
import subprocess
import sys
from pathlib import Path

ROUTE_M = 30.0
DEADLINE_S = 15.0
# Mission mode: the deadline of an operator in a hurry; the speed a careful operator allows
# near people; below this padding the robot bumps into a crowd on most runs; quiet commands
# (a behavior watched, nothing changed) before the world changes.
HURRIED_DEADLINE_S = 10.0
CAREFUL_SPEED = 3.0
CROWD_PADDING_M = 1.0
CHANGE_AFTER = 40
# The share of failed or interrupted commands whose reason the operator states.
EXPLAINS = 1.0 / 3.0


class ProtocolError(Exception):
    """The server answered a request with an error reply."""


class Adapter:
    """One JSON-lines conversation with the server: a request out, a reply back."""

    def __init__(self, reader, writer, closer):
        self._reader = reader
        self._writer = writer
        self._closer = closer

    @classmethod
    def spawn(cls, server, domain, cases, seed, mission=False):
        command = [server, "serve", "--domain", domain, "--cases", cases, "--seed", str(seed)]
        if mission:
            command.append("--mission")
        process = subprocess.Popen(
            command,
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
        )

        def close():
            process.stdin.close()
            if process.wait() != 0:
                raise ProtocolError(f"the server exited with status {process.returncode}")

        return cls(process.stdout, process.stdin, close)

    @classmethod
    def connect(cls, address):
        host, port = address.rsplit(":", 1)
        sock = socket.create_connection((host, int(port)))
        stream = sock.makefile("rw", encoding="utf-8", newline="\n")
        return cls(stream, stream, sock.close)

    def ask(self, request):
        # allow_nan=False: JSON has no NaN, and the server would refuse the line anyway.
        self._writer.write(json.dumps(request, allow_nan=False) + "\n")
        self._writer.flush()
        line = self._reader.readline()
        if not line:
            raise ProtocolError("the server closed the connection")
        reply = json.loads(line)
        if "error" in reply:
            raise ProtocolError(f"{request} -> {reply['error']}")
        return reply

    def close(self):
        self._closer()


class World:
    """The route, the robot and the operator watching it. Nothing here is told to the
    robot but the outcome of each command."""

    def __init__(self, rng):
        self.rng = rng
        self.deadline_s = DEADLINE_S
        # A careful operator's speed limit near people, if any.
        self.speed_limit = None
        # The route is crowded: the robot needs more padding to keep clear of people.
        self.crowded = False
        # The operator trusts the robot and stops reacting to its bumps.
        self.complacent = False
        self.changes = 0

    def run(self, behavior):
        """Performs one command with `behavior`; returns the outcome to report."""
        speed, padding = behavior["speed"], behavior["padding"]
        duration = ROUTE_M / speed + self.rng.uniform(0.0, 2.0)
        if padding > 1.5 and self.rng.random() < 0.9:
            # The robot knows it is stuck: it perceives it.
            return self.report("failed", duration, observed=["stuck"], reason="stuck")
        # Too little padding, or too fast to stop in time: collisions are likely.
        tight = padding < (CROWD_PADDING_M if self.crowded else 0.5)
        collision = 0.8 if tight or speed > 6.0 else 0.03
        if self.rng.random() < collision:
            if self.complacent:
                # The operator lets the bump pass; the robot felt it all the same.
                return {
                    "outcome": "completed",
                    "weight": 1.0,
                    "duration_s": round(duration, 3),
                    "observed": ["collision"],
                }
            # The operator stops the robot at the collision, part way along the route; the
            # robot felt the bump.
            return self.report(
                "interrupted",
                duration * self.rng.uniform(0.2, 0.9),
                observed=["collision"],
                reason="collision",
            )
        if self.speed_limit is not None and speed > self.speed_limit and self.rng.random() < 0.9:
            # The robot notices it passed people fast; the operator stops it.
            return self.report(
                "interrupted",
                duration * self.rng.uniform(0.2, 0.9),
                observed=["near-person-fast"],
                reason="too-fast-near-people",
            )
        if duration > self.deadline_s and self.rng.random() < 0.95:
            # The deadline is the operator's: the robot learns of it only if told.
            return self.report("interrupted", self.deadline_s, observed=[], reason="deadline")
        return {"outcome": "completed", "weight": 1.0, "duration_s": round(duration, 3)}

    def change(self, behavior):
        """The mission's next change; returns what changed, or None when nothing is left to
        change. A demonstration: the new operator is picked so that it matters for the
        behavior in use."""
        self.changes += 1
        if self.changes == 1 and behavior["speed"] > CAREFUL_SPEED:
            self.speed_limit = CAREFUL_SPEED
            return f"a careful operator takes over ({CAREFUL_SPEED:g} m/s at most near people)"
        if self.changes == 1:
            self.deadline_s = HURRIED_DEADLINE_S
            return f"an operator in a hurry takes over ({HURRIED_DEADLINE_S:g} s deadline)"
        if self.changes == 2:
            self.crowded = self.complacent = True
            return "the route gets crowded, and the operator, trusting the robot, looks away"
        return None

    def report(self, outcome, duration, observed, reason):
        """What the robot knows of a failed or interrupted command: what it perceived,
        and the operator's reason only when the operator says it (a third of the time)."""
        line = {"outcome": outcome, "weight": 1.0, "duration_s": round(duration, 3)}
        if observed:
            line["observed"] = observed
        if self.rng.random() < EXPLAINS:
            line["stated"] = reason
        return line


def plural(count, noun):
    return f"{count} {noun}" if count == 1 else f"{count} {noun}s"


def show(behavior):
    return f"speed={behavior['speed']} m/s, padding={behavior['padding']} m"


def episode(adapter, world, number):
    """One operator, one adaptation episode; returns the settled reply."""
    behavior = adapter.ask({"request": "begin"})["behavior"]
    while True:
        reply = adapter.ask(world.run(behavior))
        if reply["ok"] == "switch":
            behavior = reply["behavior"]
            # Why, in one plain sentence fit for an operator's screen.
            print(f"  {reply['explanation']['sentence']}")
        elif reply["ok"] == "settled":
            retained = reply["retained"]
            note = f", retained case #{retained}" if retained is not None else ""
            print(
                f"episode {number}: settled on {show(reply['behavior'])} after "
                f"{plural(reply['behaviors_evaluated'], 'behavior')} and "
                f"{plural(reply['commands'], 'command')} "
                f"({reply['reused']} from cases, {reply['searched']} searched{note})"
            )
            return reply


def mission(adapter, world, commands):
    """One operator's mission of `commands` commands in mission mode: the controller keeps
    reporting outcomes after the robot settles, follows re-adaptations and answers alerts.
    Returns the counts of settled replies, re-adaptations after settling and alerts."""
    behavior = adapter.ask({"request": "begin"})["behavior"]
    # While a settled behavior is watched: the command since which nothing changed.
    quiet_since = None
    counts = {"settled": 0, "readapted": 0, "alerts": 0}
    for command in range(1, commands + 1):
        reply = adapter.ask(world.run(behavior))
        kind = reply["ok"]
        if kind == "settled":
            quiet_since = command
            counts["settled"] += 1
            print(f"command {command}: settled on {show(reply['behavior'])}")
        elif kind == "switch":
            if quiet_since is not None:
                # The settled behavior's trust fell: the server started a new episode.
                counts["readapted"] += 1
                print(f"command {command}: trust in {show(behavior)} fell, re-adapting")
            quiet_since = None
            print(f"  {reply['explanation']['sentence']}")
        elif kind == "alert":
            # The robot's own record disagrees with the operator's trust: ask the operator
            # to supervise (it does: it reacts to bumps again).
            counts["alerts"] += 1
            print(f"command {command}: the robot asks the operator to supervise")
            print(f"  {reply['sentence']}")
            world.complacent = False
        behavior = reply["behavior"]
        if quiet_since is not None and command - quiet_since == CHANGE_AFTER:
            quiet_since = command
            change = world.change(behavior)
            if change is not None:
                print(f"command {command}: {change} (the robot is not told)")
    return counts


def find_server():
    """The trustcbr binary to spawn, or None: $TRUSTCBR, then PATH, then this repository's
    newest build."""
    if os.environ.get("TRUSTCBR"):
        return os.environ["TRUSTCBR"]
    on_path = shutil.which("trustcbr")
    if on_path:
        return on_path
    repository = Path(__file__).resolve().parent.parent
    builds = [repository / "target" / profile / "trustcbr" for profile in ("release", "debug")]
    builds = [b for b in builds if b.is_file() and os.access(b, os.X_OK)]
    return str(max(builds, key=lambda b: b.stat().st_mtime)) if builds else None


NO_SERVER = (
    "cannot find the trustcbr binary: pass --server PATH (or set TRUSTCBR=PATH), install it "
    "with `cargo install --path .` (then `trustcbr` is on PATH), or build it in this "
    "repository with `cargo build --release`"
)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--server",
        help="the trustcbr binary to spawn (default: $TRUSTCBR, trustcbr on PATH, or this repository's build)",
    )
    parser.add_argument("--connect", metavar="HOST:PORT", help="talk to a running `serve --listen` instead")
    parser.add_argument("--cases", default="cases.db", help="the case base file (spawn mode)")
    parser.add_argument("--episodes", type=int, default=20)
    parser.add_argument(
        "--mission",
        type=int,
        nargs="?",
        const=600,
        metavar="COMMANDS",
        help="run one mission of COMMANDS commands (default 600) in mission mode instead of episodes",
    )
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()

    if args.connect:
        adapter = Adapter.connect(args.connect)
    else:
        server = args.server or find_server()
        if server is None:
            print(NO_SERVER, file=sys.stderr)
            return 2
        try:
            adapter = Adapter.spawn(
                server, "movement", args.cases, args.seed, mission=args.mission is not None
            )
        except OSError as e:
            print(f"cannot run {server}: {e.strerror}; pass a trustcbr binary with --server PATH", file=sys.stderr)
            return 2
    world = World(random.Random(args.seed))
    try:
        start = adapter.ask({"request": "state"})
        print(f"domain {start['domain']}: {start['cases']} cases at start")
        if args.mission is not None:
            counts = mission(adapter, world, args.mission)
            cases = adapter.ask({"request": "cases"})["cases"]
            print(
                f"mission: {args.mission} commands, settled {plural(counts['settled'], 'time')}, "
                f"re-adapted {plural(counts['readapted'], 'time')} after settling, "
                f"{plural(counts['alerts'], 'alert')}, cases: {len(cases)}"
            )
            return 0
        settled = [episode(adapter, world, n + 1) for n in range(args.episodes)]
        half = max(1, len(settled) // 2)
        mean = lambda replies: sum(r["behaviors_evaluated"] for r in replies) / max(1, len(replies))
        cases = adapter.ask({"request": "cases"})["cases"]
        print(
            f"episodes: {len(settled)}, trustworthy: {sum(r['trustworthy'] for r in settled)}, "
            f"mean behaviors evaluated: first half {mean(settled[:half]):.2f}, "
            f"second half {mean(settled[half:]):.2f}, cases: {len(cases)}"
        )
    except ProtocolError as e:
        print(f"protocol error: {e}", file=sys.stderr)
        return 1
    finally:
        adapter.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
