"""A load probe of ``trustcbr console``: many participants at once over the page's own API.

Starts ``trustcbr console`` on a temporary SQLite database with tests/browser/study.ron
(its ``commands`` and ``behaviors`` raised, so sessions are long enough to load the server)
and runs PARTICIPANTS participants at once, one thread each, over urllib, each going
through its whole session as fast as the API answers: ``POST /api/shown`` for each run,
then ``POST /api/stop`` at a random moment of it (or ``POST /api/end``), a statement when
asked (a random cause, or none), a rating when asked, and ``POST /api/leave`` at the end.
Some requests are sent twice (a retry after a lost reply), which must record nothing more.
Every request is timed. Then the study is exported, and every acknowledged request's
events must be in events.jsonl, in order, once each.

Prints the participants, requests, events, the events lost and duplicated (both must be
0), and the round trip of ``POST /api/stop`` (the stop is stored before the reply):
p50, p99 and max; then the same for every request.

    python3 docs/probes/console_load.py [--participants 20] [--commands 40] [--paced]

``--paced``: each participant waits for each run as the page plays it (the study's run
time to the stop, or to the end, divided by its speedup, 40), so the load is what 20
pages send rather than as much as the API takes.

``--browser N`` measures instead, in headless Chromium through Playwright, the time from
a participant's key press (Date.now() in the page's keydown listener) to the server's
``at_ms`` of the stop it made (stamped when the server takes the request up) and to the
reply's arrival in the page, over N stops, all on one machine (one clock).

The binary is ``$TRUSTCBR_BIN`` or ``target/debug/trustcbr``; Chromium is
``$TRUSTCBR_CHROMIUM`` or ``/usr/bin/chromium``.
"""

from __future__ import annotations

import argparse
import json
import os
import random
import re
import sys
import tempfile
import threading
import time
from collections import Counter
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple

ROOT = Path(__file__).resolve().parents[2]
STUDY = ROOT / "tests" / "browser" / "study.ron"
# The console process the browser test starts, started here the same way.
sys.path.insert(0, str(ROOT / "tests" / "browser"))
from console_process import Console  # noqa: E402


def variant(folder: Path, commands: int, behaviors: int, speedup: Optional[float]) -> Path:
    """tests/browser/study.ron with other limits (and speedup)."""
    text = STUDY.read_text()
    text = re.sub(r"commands: \d+", f"commands: {commands}", text)
    text = re.sub(r"behaviors: \d+", f"behaviors: {behaviors}", text)
    if speedup is not None:
        text = re.sub(r"speedup: [0-9.]+", f"speedup: {speedup}", text)
    path = folder / "study.ron"
    path.write_text(text)
    return path


def percentile(values: List[float], q: float) -> float:
    """The q-th percentile (nearest rank) of `values`."""
    ordered = sorted(values)
    rank = max(1, min(len(ordered), round(q / 100 * len(ordered) + 0.5)))
    return ordered[rank - 1]


def summary_ms(values: List[float]) -> str:
    if not values:
        return "none"
    return (
        f"p50 {percentile(values, 50) * 1000:.1f} ms, p99 {percentile(values, 99) * 1000:.1f} ms,"
        f" max {max(values) * 1000:.1f} ms (n={len(values)})"
    )


# ---------------------------------------------------------------------- API load


Expected = Tuple[str, Dict[str, Any]]


class Participant(threading.Thread):
    """One participant's whole session, as fast as the API answers."""

    def __init__(
        self, console: Console, seed: int, retry_share: float, speedup: Optional[float]
    ) -> None:
        super().__init__()
        self.console = console
        # With a speedup, each run is waited for as the page plays it (to the stop, or to
        # its end), divided by the speedup; without, no run is waited for.
        self.speedup = speedup
        self.rng = random.Random(seed)
        self.retry_share = retry_share
        self.pseudonym = ""
        self.expected: List[Expected] = []  # the events acknowledged requests recorded
        self.timings: Dict[str, List[float]] = {}
        self.failure: Optional[str] = None

    def call(self, method: str, path: str, body: Any = None, token: Optional[str] = None) -> Any:
        started = time.perf_counter()
        status, reply = self.console.request(method, path, body, token)
        took = time.perf_counter() - started
        self.timings.setdefault(f"{method} {path}", []).append(took)
        if status >= 300 and not (status == 204 and path == "/api/leave"):
            raise RuntimeError(f"{method} {path} {body}: {status} {reply}")
        return reply

    def twice(self, path: str, body: Any, token: str) -> Any:
        """POST, and sometimes the same again (a retry after a lost reply): the second
        must answer the same state and record nothing."""
        state = self.call("POST", path, body, token)
        if self.rng.random() < self.retry_share:
            again = self.call("POST", path, body, token)
            if again != state:
                raise RuntimeError(f"POST {path} {body} repeated: {again} after {state}")
        return state

    def watch(self, run_s: float) -> None:
        """Waits while the page would play `run_s` seconds of a run (when paced)."""
        if self.speedup:
            time.sleep(run_s / self.speedup)

    def run(self) -> None:
        try:
            self.session()
        except Exception as e:  # reported by the main thread
            self.failure = f"{self.pseudonym or 'a participant'}: {e}"

    def session(self) -> None:
        enrolled = self.call("POST", "/api/participants", {"consent": True})
        token = str(enrolled["token"])
        self.pseudonym = str(enrolled["participant"])
        self.expected.append(("enrolled", {}))
        state = self.call("GET", "/api/session", token=token)
        statements = bool(state["condition"]["statements"])
        causes = [c["name"] for c in state.get("causes", [])] + [None]
        while state["phase"] != "done":
            phase = state["phase"]
            if phase == "watch":
                k = state["command"]["index"]
                run = state["command"]["run"]
                state = self.call("POST", "/api/shown", {"command": k}, token)
                self.expected.append(("shown", {"command": k}))
                if self.rng.random() < 0.6:
                    at = round(self.rng.uniform(0, run["duration_s"]), 3)
                    self.watch(at)
                    state = self.twice("/api/stop", {"command": k, "at_s": at}, token)
                    self.expected.append(("stop", {"command": k, "at_s": at}))
                    if not statements:
                        self.expected.append(("decision", {"command": k}))
                else:
                    self.watch(float(run["duration_s"]))
                    state = self.twice("/api/end", {"command": k}, token)
                    self.expected += [("end", {"command": k}), ("decision", {"command": k})]
            elif phase == "state-cause":
                k = state["command"]["index"]
                cause = self.rng.choice(causes)
                state = self.twice("/api/statement", {"command": k, "cause": cause}, token)
                self.expected += [
                    ("statement", {"command": k, "cause": cause}),
                    ("decision", {"command": k}),
                ]
            elif phase == "rate":
                n = state["rating"]["number"]
                value = self.rng.randint(1, state["rating"]["scale"]["points"])
                state = self.twice("/api/rating", {"rating": n, "value": value}, token)
                self.expected.append(("rating", {"number": n, "value": value}))
            else:
                raise RuntimeError(f"unknown phase {phase}")
        self.call("POST", "/api/leave", {"token": token})
        self.expected.append(("left", {}))


# The fields of each kind of event the probe checks.
FIELDS = {
    "enrolled": [],
    "shown": ["command"],
    "resumed": ["command"],
    "stop": ["command", "at_s"],
    "statement": ["command", "cause"],
    "end": ["command"],
    "decision": ["command"],
    "rating": ["number", "value"],
    "left": [],
}


def event_key(kind: str, fields: Dict[str, Any]) -> str:
    """The event as a comparable string (whole numbers compare equal as 6 and 6.0)."""

    def plain(value: Any) -> Any:
        return int(value) if isinstance(value, float) and value.is_integer() else value

    checked = {f: plain(fields.get(f)) for f in FIELDS.get(kind, [])}
    return json.dumps([kind, checked], sort_keys=True)


def compare(expected: List[Expected], recorded: List[Dict[str, Any]]) -> Tuple[int, int, List[str]]:
    """(lost, duplicated, differences) of a participant's recorded events against those its
    acknowledged requests made: lost, an expected event not recorded; duplicated, an event
    recorded more often than expected (or never expected)."""
    problems = []
    seqs = [e["seq"] for e in recorded]
    if seqs != list(range(len(recorded))):
        problems.append(f"seq not contiguous from 0: {seqs}")
    want = [event_key(kind, fields) for kind, fields in expected]
    have = [event_key(e["kind"], e) for e in recorded]
    lost = sum((Counter(want) - Counter(have)).values())
    duplicated = sum((Counter(have) - Counter(want)).values())
    if want != have and not lost and not duplicated:
        problems.append("events recorded in another order than their requests were acknowledged")
    return lost, duplicated, problems


def api_load(binary: str, participants: int, commands: int, seed: int, paced: bool) -> int:
    with tempfile.TemporaryDirectory(prefix="console-load-") as scratch:
        folder = Path(scratch)
        study = variant(folder, commands, max(2, commands // 2), None)
        speedup = float(re.findall(r"speedup: ([0-9.]+)", study.read_text())[0]) if paced else None
        console = Console(binary, study, folder)
        try:
            threads = [Participant(console, seed + i, 0.1, speedup) for i in range(participants)]
            started = time.perf_counter()
            for t in threads:
                t.start()
            for t in threads:
                t.join()
            wall = time.perf_counter() - started
        finally:
            console.stop()
        failures = [t.failure for t in threads if t.failure]
        if failures:
            print("\n".join(failures), file=sys.stderr)
            return 1
        out = folder / "export"
        events = console.export_events(out)
        errors = "\n".join(
            line
            for line in (folder / "console.stderr").read_text(errors="replace").splitlines()
            if "researcher's page" not in line
        )
    lost = duplicated = 0
    problems = []
    for t in threads:
        mine = sorted(
            (e for e in events if e["participant"] == t.pseudonym), key=lambda e: e["seq"]
        )
        missing, extra, differ = compare(t.expected, mine)
        lost += missing
        duplicated += extra
        problems += [f"{t.pseudonym}: {line}" for line in differ]
    timings: Dict[str, List[float]] = {}
    for t in threads:
        for name, values in t.timings.items():
            timings.setdefault(name, []).extend(values)
    requests = sum(len(v) for v in timings.values())
    print(
        f"participants {participants}, requests {requests} in {wall:.1f} s"
        f" ({requests / wall:.0f}/s), events {len(events)}"
        f" (expected {sum(len(t.expected) for t in threads)}), lost {lost}, duplicated {duplicated}"
    )
    print(f"POST /api/stop round trip: {summary_ms(timings.get('POST /api/stop', []))}")
    for name in sorted(timings):
        print(f"  {name}: {summary_ms(timings[name])}")
    every = [x for v in timings.values() for x in v]
    print(f"  every request: {summary_ms(every)}")
    for line in problems[:10]:
        print(f"  {line}", file=sys.stderr)
    if errors:
        print(f"console's stderr:\n{errors}", file=sys.stderr)
    return 0 if lost == 0 and duplicated == 0 and not problems else 1


# ---------------------------------------------------------------------- in a browser

# Date.now() at every space-bar keydown the page sees, before the page's own listener
# (capture phase, on window), and the moment each POST /api/stop reply arrived.
STAMPS = """
window.__keys = [];
window.addEventListener("keydown", (e) => {
  if (e.key === " ") window.__keys.push(Date.now());
}, true);
window.__replies = [];
new PerformanceObserver((list) => {
  for (const e of list.getEntries()) {
    if (e.name.endsWith("/api/stop")) window.__replies.push(performance.timeOrigin + e.responseEnd);
  }
}).observe({ type: "resource", buffered: true });
"""

READY = """
() => {
  const phase = document.getElementById("main").getAttribute("data-phase");
  if (phase !== "watch") return phase;
  return document.getElementById("interrupt").disabled ? false : "run";
}
"""


def browser_latency(binary: str, stops: int, seed: int) -> int:
    from playwright.sync_api import Page, sync_playwright
    from playwright.sync_api import TimeoutError as PlaywrightTimeout

    rng = random.Random(seed)
    chromium = os.environ.get("TRUSTCBR_CHROMIUM", "/usr/bin/chromium")
    to_stored: List[float] = []
    to_reply: List[float] = []

    def one_session(page: Page, console: Console) -> None:
        page.goto(console.url + "/")
        page.click("#start")
        while len(to_stored) < stops:
            phase = page.wait_for_function(READY, polling="raf", timeout=30_000).json_value()
            if phase == "done":
                return
            if phase == "run":
                progress = re.search(r"Commands: (\d+)", page.text_content("#progress") or "")
                if progress is None:
                    raise RuntimeError("no progress line")
                k = int(progress.group(1))
                page.wait_for_timeout(rng.uniform(20, 300))
                keys_before = len(page.evaluate("window.__keys"))
                replies_before = len(page.evaluate("window.__replies"))
                page.keyboard.press("Space")
                page.wait_for_function("() => document.getElementById('interrupt').disabled")
                keys = page.evaluate("window.__keys")
                try:  # the reply to the stop, unless the run had ended before the key press
                    page.wait_for_function(
                        "(n) => window.__replies.length > n", arg=replies_before, timeout=3000
                    )
                except PlaywrightTimeout:
                    continue
                if len(keys) == keys_before:
                    continue
                pressed = float(keys[-1])
                replied = float(page.evaluate("window.__replies")[-1])
                _, events = console.request(
                    "GET",
                    f"/api/admin/events?participant={pseudonym(page, console)}",
                    token=console.admin,
                )
                stop = [e for e in events if e["kind"] == "stop" and e["command"] == k]
                if stop:
                    to_stored.append((stop[0]["at_ms"] - pressed) / 1000)
                    to_reply.append((replied - pressed) / 1000)
            elif phase == "state-cause":
                page.click("#cause-options input >> nth=0")
                page.click("#cause-continue")
                page.wait_for_function(
                    "() => document.getElementById('main').getAttribute('data-phase')"
                    " !== 'state-cause'"
                )
            elif phase == "rate":
                page.click("#rate-form input >> nth=3")
                page.click("#rate-continue")
                page.wait_for_function(
                    "() => !document.querySelector('#rate-form input:checked')"
                    " || document.getElementById('main').getAttribute('data-phase') !== 'rate'"
                )

    def pseudonym(page: Page, console: Console) -> str:
        token = page.evaluate("localStorage.getItem('trustcbr-console-token')")
        _, state = console.request("GET", "/api/session", token=token)
        return str(state["participant"])

    with tempfile.TemporaryDirectory(prefix="console-latency-") as scratch:
        folder = Path(scratch)
        # Slower runs (speedup 4: 1 to 8 s each), so a stop at a random moment of a run
        # finds it still under way.
        study = variant(folder, 40, 20, 4.0)
        console = Console(binary, study, folder)
        try:
            with sync_playwright() as p:
                browser = p.chromium.launch(
                    executable_path=chromium,
                    args=["--no-sandbox", "--disable-gpu", "--disable-background-networking"]
                    + ["--disable-component-update", "--disable-sync", "--no-first-run"]
                    + ["--disable-quic"],
                )
                while len(to_stored) < stops:
                    context = browser.new_context(viewport={"width": 800, "height": 600})
                    context.add_init_script(STAMPS)
                    one_session(context.new_page(), console)
                    context.close()
                browser.close()
        finally:
            console.stop()
    print(f"browser: {len(to_stored)} stops by the space bar")
    print(f"  keydown to the server's at_ms: {summary_ms(to_stored)}")
    print(f"  keydown to the reply in the page: {summary_ms(to_reply)}")
    return 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--participants", type=int, default=20)
    parser.add_argument("--commands", type=int, default=40)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--browser", type=int, metavar="N", default=0, help="N stops in Chromium")
    parser.add_argument(
        "--paced", action="store_true", help="wait for each run as the page plays it"
    )
    args = parser.parse_args()
    binary = os.environ.get("TRUSTCBR_BIN", str(ROOT / "target/debug/trustcbr"))
    if args.browser:
        return browser_latency(binary, args.browser, args.seed)
    return api_load(binary, args.participants, args.commands, args.seed, args.paced)


if __name__ == "__main__":
    sys.exit(main())
