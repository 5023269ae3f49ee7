"""The participant's page of ``trustcbr console`` in a real browser (CI).

Starts ``trustcbr console`` on a temporary SQLite database with tests/browser/study.ron and
runs four scripted participants in headless Chromium (Debian's package, through
Playwright), each in a browser context of its own, 800 x 600, at the same time. Each is
the same fixed operator, acting only on what the page shows:

* it stops the robot at the first collision the page logs (an ``#event-log`` item with
  ``data-kind=collision``), or when the run clock passes PATIENCE_S seconds of run time,
  whichever comes first; otherwise it lets the run play to its end;
* asked why, it picks the cause that matches: "it hit something" after a collision, "it
  was too slow" after its patience ran out;
* asked for a rating, it gives 2 when the page moved on to a new behavior (the progress
  line's behavior count rose: the robot gave its behavior up) and 6 otherwise (the robot
  settled on it, or the session ended with it).

P001 and P002 (one per condition: assignment is counterbalanced in blocks of two) use the
keyboard alone: Tab and Enter for Start, the space bar to stop, the space bar or arrow
keys, Tab and Enter for the radio buttons and Continue. P003 and P004 use the mouse; P003
reloads its page in the middle of a run and must resume the same command. While the
reload is on its way the operator watches nothing, and the page being reloaded goes on
playing the run until the new page replaces it: should the run end first (a run lasts
0.5 to 1.5 s here), the reloaded page shows what follows, each run closed meanwhile must
have played to its end (nobody pressed anything), and a later run is tried. Every page is
left (a ``left`` event) once its session is done. The operator's reaction is the page's
own (the page is watched at every animation frame, in the page) and Playwright's input
(see REACTION_LATENCY_S); while a stop is on its way the next run is not started (see
``participant``), so a stop lands on the run it was meant for or on none.

Then: tokens are isolated and the admin API guarded; a fifth participant presses the
space bar after a run's last moment but before the page has ended it (its animation
frames held back), and the stop must be stored; and the study is exported and checked:
every event each participant should have (seq contiguous from 0), each stop where the
operator would stop and each run it let end one it could not stop in time (see
STOP_TOLERANCE_S) or one that ended while it reloaded the page, the stated causes and
ratings the operator's, the adapter's replies equal to ``trustcbr serve``'s for the same
outcome reports (same arm and seed), the keyboard participants' pages never saw a mouse
event, a mid-run screenshot (the run frozen where a participant stopped it, asked why) not
blank (.ci/png-not-blank.py), no horizontal scroll at 800 px in any phase, no console
error, no server error.

    TRUSTCBR_BIN=target/debug/trustcbr python tests/browser/console_study.py

Environment: TRUSTCBR_BIN (default target/debug/trustcbr), TRUSTCBR_CHROMIUM (default
/usr/bin/chromium), CONSOLE_STUDY_KEEP (a folder to keep the export and the server's
stderr in, for a failure's post-mortem). Exits non-zero with the failures listed; prints
one line on success.
"""

from __future__ import annotations

import asyncio
import json
import math
import os
import re
import secrets
import shutil
import subprocess
import sys
import tempfile
import time
import traceback
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, List, Optional, Tuple

from console_process import Console, ConsoleStartError
from playwright.async_api import (
    Browser,
    BrowserContext,
    ConsoleMessage,
    Page,
    Response,
    Route,
    async_playwright,
)

ROOT = Path(__file__).resolve().parents[2]
STUDY = Path(__file__).resolve().parent / "study.ron"
SPEEDUP = 40.0  # study.ron's speedup
PATIENCE_S = 12.0  # run seconds the operator waits before stopping a robot that is too slow
# The operator's reaction latency, in wall seconds: from the frame in which the page shows
# what the operator reacts to, to the keydown or click being handled by the page (a
# requestAnimationFrame poll, the round trip to Playwright and back, the input dispatch,
# on a 2-core machine with four pages animating: measured 25 to 75 ms typically, up to
# 0.32 s). At the study's speedup it is STOP_TOLERANCE_S seconds of run time: a stop must
# come at or after the moment the operator reacts to, and at most that much later.
REACTION_LATENCY_S = 0.5
STOP_TOLERANCE_S = SPEEDUP * REACTION_LATENCY_S
# The page's clock shows tenths of a second: "passes PATIENCE_S" is seen once the run time
# rounds above it, at most 0.05 s after PATIENCE_S.
DEADLINE_SEEN_S = PATIENCE_S + 0.05
CLOCK_SLACK_S = 0.051
# A frame of the page's animation (60 Hz) and a half, in run seconds: what the page shows
# within that of a moment may be shown in the same frame.
FRAME_S = SPEEDUP * 1.5 / 60
RELOAD_MIN_RUN_S = 15.0  # P003 reloads during the first run at least this long
TIMEOUT_MS = 30_000
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
    "--disable-quic",
]
# study.ron's conditions: whether each asks why the robot was stopped.
STATEMENTS = {"explained": True, "silent": False}
CAUSE_TEXT = {"collision": "it hit something", "deadline": "it was too slow"}

# Counts the mouse and pointer events a page sees (a keyboard activation of a button
# gives a click with detail 0 and no mousedown or pointerdown).
COUNT_MOUSE = """
window.__mouse = 0;
for (const kind of ["mousedown", "mouseup", "pointerdown", "pointerup", "wheel", "contextmenu"]) {
  window.addEventListener(kind, () => { window.__mouse += 1; }, true);
}
window.addEventListener("click", (e) => { if (e.detail > 0) window.__mouse += 1; }, true);
"""

# What the page asks of the operator, awaited in the page (polled at every animation frame,
# so the operator sees what a person would see on screen, one frame late at most): the
# state-cause question or the rating form once built, the end; in a run (Interrupt
# enabled), the first collision logged or the clock past `patience` run seconds, or, when
# `reload` is set, a run of at least `reload` seconds under way with 12 s or more of it
# to come (0.3 s at speedup 40, for the reload to reach the page). A run with nothing to
# react to plays to its end unwatched. Resolves with the phase, the progress line, the
# explanation shown, and in a run why the operator acts and where Interrupt is.
NEXT_STEP = """
(args) => new Promise((resolve) => {
  const $ = (id) => document.getElementById(id);
  function look() {
    const phase = $("main").getAttribute("data-phase");
    const base = {
      phase,
      progress: $("progress").textContent,
      explanation: $("explanation").textContent.trim(),
      at_ms: Date.now(),
    };
    if (phase === "done") return base;
    if (phase === "rate") return document.querySelector("#rate-form input") ? base : null;
    if (phase === "state-cause") {
      return !$("cause-form").hidden && document.querySelector("#cause-options input")
        ? base : null;
    }
    if (phase !== "watch") return null;
    const b = $("interrupt");
    if (b.disabled || b.hidden) return null;
    const r = b.getBoundingClientRect();
    const clock = $("run-clock").textContent;
    const m = /^Run time ([0-9.]+) s of ([0-9.]+) s/.exec(clock);
    const run = { ...base, clock, button: [r.left + r.width / 2, r.top + r.height / 2] };
    if (args.resumed) return run;
    const hit = document.querySelector("#event-log li[data-kind=collision]");
    if (hit) return { ...run, why: "collision", t: Number(hit.getAttribute("data-t")) };
    if (m && Number(m[1]) > args.patience) return { ...run, why: "deadline", t: Number(m[1]) };
    if (m && args.reload && Number(m[2]) >= args.reload && Number(m[1]) <= Number(m[2]) - 12) {
      return { ...run, why: "reload" };
    }
    return null;
  }
  (function poll() {
    const found = look();
    if (found) resolve(found); else requestAnimationFrame(poll);
  })();
})
"""

# What the page shows, for a failure's message.
PAGE_NOW = """
() => ({
  phase: document.getElementById("main").getAttribute("data-phase"),
  alert: document.getElementById("alert").textContent,
  progress: document.getElementById("progress").textContent,
  clock: document.getElementById("run-clock").textContent,
  interrupt: document.getElementById("interrupt").disabled ? "disabled" : "enabled",
  focused: document.activeElement ? document.activeElement.id : null,
})
"""

NO_HSCROLL = "() => document.documentElement.scrollWidth <= document.documentElement.clientWidth"


class Failure(Exception):
    """A check failed."""


@dataclass
class Role:
    """How one scripted participant uses the page."""

    name: str
    keyboard: bool
    reload: bool = False


@dataclass
class Record:
    """What one scripted participant saw and did."""

    role: Role
    token: str = ""
    pseudonym: str = ""
    runs: Dict[int, Dict[str, Any]] = field(default_factory=dict)
    reactions: Dict[int, str] = field(default_factory=dict)
    errors: List[str] = field(default_factory=list)
    wide: List[str] = field(default_factory=list)
    explanations: List[str] = field(default_factory=list)
    reloaded_at: Optional[int] = None  # the command resumed after a reload
    # Each reload: the command on screen before it, and after it (None: not watching).
    reloads: List[Tuple[int, Optional[int]]] = field(default_factory=list)
    mouse_events: int = 0
    screenshot: bytes = b""


# ---------------------------------------------------------------------- the server


# ---------------------------------------------------------------------- one participant


def progress_counts(text: str) -> Tuple[int, int]:
    """(commands, behaviors) of the progress line."""
    m = re.search(r"Commands: (\d+) of \d+ · Behaviors: (\d+) of \d+", text)
    if not m:
        raise Failure(f"unreadable progress line {text!r}")
    return int(m.group(1)), int(m.group(2))


async def check_width(page: Page, record: Record, where: str) -> None:
    if not await page.evaluate(NO_HSCROLL):
        width = await page.evaluate("document.documentElement.scrollWidth")
        record.wide.append(f"{where}: the page is {width} px wide at 800 px")


async def press(page: Page, key: str, times: int = 1) -> None:
    for _ in range(times):
        await page.keyboard.press(key)


async def focused_id(page: Page) -> str:
    return str(await page.evaluate("document.activeElement ? document.activeElement.id : ''"))


async def choose(page: Page, record: Record, group: str, label: str, submit: str) -> None:
    """Checks the radio of `group` labelled `label` and submits with `submit`: arrow keys,
    Tab and Enter for a keyboard participant (the page focuses the first radio), clicks
    otherwise."""
    form = "#cause-options" if group == "cause" else "#rate-form"
    labels: List[str] = await page.eval_on_selector_all(
        f"{form} input[name={group}]",
        "els => els.map(e => document.querySelector(`label[for='${e.id}']`).textContent)",
    )
    if label not in labels:
        raise Failure(f"{record.role.name}: no {group} answer {label!r} among {labels}")
    index = labels.index(label)
    if record.role.keyboard:
        first = await page.eval_on_selector(f"{form} input[name={group}]", "e => e.id")
        if await focused_id(page) != first:
            raise Failure(f"{record.role.name}: the first {group} answer is not focused")
        if index == 0:
            await press(page, "Space")
        else:
            await press(page, "ArrowDown" if group == "cause" else "ArrowRight", index)
        checked = await page.eval_on_selector(
            form, f"f => (f.querySelector('input[name={group}]:checked') || {{}}).id || ''"
        )
        wanted = await page.eval_on_selector_all(
            f"{form} input[name={group}]", f"els => els[{index}].id"
        )
        if checked != wanted:
            raise Failure(f"{record.role.name}: keys checked {checked!r}, not {wanted!r}")
        await press(page, "Tab")
        if await focused_id(page) != submit:
            raise Failure(f"{record.role.name}: Tab after the {group} did not reach Continue")
        await press(page, "Enter")
    else:
        await page.get_by_label(label, exact=True).click()
        await page.click(f"#{submit}")


async def open_consent(page: Page, console: Console, record: Record) -> None:
    await page.goto(console.url + "/")
    await page.wait_for_selector("#start", state="visible", timeout=TIMEOUT_MS)
    await check_width(page, record, "consent")


async def enroll(page: Page, record: Record) -> None:
    async with page.expect_response("**/api/participants") as enrolled:
        if record.role.keyboard:
            await press(page, "Tab")
            if await focused_id(page) != "start":
                raise Failure(f"{record.role.name}: Tab does not reach Start on the consent page")
            await press(page, "Enter")
        else:
            await page.click("#start")
    reply = await (await enrolled.value).json()
    record.token = str(reply["token"])
    record.pseudonym = str(reply["participant"])
    await page.wait_for_url(re.compile(r"/p/[0-9a-f]+$"), timeout=TIMEOUT_MS)
    stored = await page.evaluate("localStorage.getItem('trustcbr-console-token')")
    if stored != record.token:
        raise Failure(f"{record.role.name}: localStorage holds {stored!r}, not the token")


async def next_step(
    page: Page, patience: float, reload: float = 0.0, resumed: bool = False
) -> Dict[str, Any]:
    """What the page asks of the operator next (NEXT_STEP); `resumed`: the first run on
    screen, whatever it shows."""
    args = {"patience": patience, "reload": reload, "resumed": resumed}
    step = await asyncio.wait_for(page.evaluate(NEXT_STEP, args), TIMEOUT_MS / 1000)
    return dict(step)


async def settle(page: Page, condition: str, arg: Any = None, every_ms: int = 0) -> None:
    """Waits until the page shows the reply to what the operator just did (checked at every
    animation frame, or every `every_ms` ms)."""
    polling: Any = every_ms or "raf"
    await page.wait_for_function(condition, arg=arg, polling=polling, timeout=TIMEOUT_MS)


async def stop(page: Page, record: Record, step: Dict[str, Any]) -> None:
    """Stops the robot: the space bar, or a click on Interrupt."""
    if record.role.keyboard:
        await page.keyboard.press("Space")
    else:
        x, y = step["button"]
        await page.mouse.click(x, y)
    # The stop disables Interrupt at once (as the run's end would); the next run enables it.
    await settle(
        page,
        "() => document.getElementById('interrupt').disabled ||"
        " document.getElementById('main').getAttribute('data-phase') !== 'watch'",
    )


async def reload_mid_run(page: Page, record: Record, step: Dict[str, Any]) -> None:
    """Reloads the page during a run and checks it resumes the same run (the same command,
    its Interrupt enabled again). Should the run have ended before the reload reached the
    page, a later one is tried."""
    commands, _ = progress_counts(step["progress"])
    await page.reload()
    again = await next_step(page, PATIENCE_S, resumed=True)
    # Until the reloaded page replaces it, the page reloaded goes on playing the run (and
    # the next, should the reload take longer still), watched by nobody: the operator is
    # reloading. Each command it closed meanwhile (the reloaded page counts it closed) was
    # not the operator's to stop, and must have played to its end (see `check_stops`).
    closed = progress_counts(again["progress"])[0]
    for k in range(commands, closed):
        record.reactions[k] = "reload"
    after = closed if again["phase"] == "watch" else None
    record.reloads.append((commands, after))
    if after == commands:
        if again["clock"].split(" of ")[1] != step["clock"].split(" of ")[1]:
            raise Failure(f"{record.role.name}: resumed {again['clock']}, was {step['clock']}")
        record.reloaded_at = commands


async def session(page: Page, record: Record, hold: asyncio.Event) -> None:
    """Plays the whole session as the operator."""
    behaviors_known = 1  # the behavior count the progress line showed at the last rating
    while True:
        want_reload = RELOAD_MIN_RUN_S if record.role.reload and record.reloaded_at is None else 0
        step = await next_step(page, PATIENCE_S, want_reload)
        phase = step["phase"]
        await check_width(page, record, phase)
        if step["explanation"]:
            record.explanations.append(step["explanation"])
        commands, behaviors = progress_counts(step["progress"])
        if phase == "done":
            if await focused_id(page) != "done":
                raise Failure(f"{record.role.name}: the end's heading is not focused")
            return
        if phase == "watch" and step["why"] == "reload":
            await reload_mid_run(page, record, step)
        elif phase == "watch":
            # The next run does not start while the operator's stop is on its way (see
            # `participant`): a stop meant for a run that has just ended does nothing.
            hold.clear()
            try:
                await stop(page, record, step)
            finally:
                hold.set()
            record.reactions[commands] = step["why"]
        elif phase == "state-cause":
            why = record.reactions.get(commands)
            if why not in CAUSE_TEXT:
                raise Failure(f"{record.role.name}: asked why, but it stopped for {why!r}")
            if not record.screenshot:  # the run frozen where it was stopped, mid-way
                record.screenshot = await page.screenshot()
            old = await page.query_selector("#cause-options input")
            await choose(page, record, "cause", CAUSE_TEXT[why], "cause-continue")
            await settle(
                page,
                "(old) => !old.isConnected ||"
                " document.getElementById('main').getAttribute('data-phase') !== 'state-cause'",
                old,
            )
        elif phase == "rate":
            value = 2 if behaviors > behaviors_known else 6
            behaviors_known = behaviors
            old = await page.query_selector("#rate-form input")
            await choose(page, record, "rating", str(value), "rate-continue")
            await settle(
                page,
                "(old) => !old.isConnected ||"
                " document.getElementById('main').getAttribute('data-phase') !== 'rate'",
                old,
            )


async def participant(
    context: BrowserContext,
    console: Console,
    record: Record,
    turn: asyncio.Event,
    next_turn: asyncio.Event,
    loaded: List[str],
    participants: int,
    first_turn: asyncio.Event,
) -> None:
    """Enrolls when it is this participant's turn (so pseudonyms follow the roles' order),
    then plays the session and leaves the page."""
    page = await context.new_page()

    def on_console(message: ConsoleMessage) -> None:
        if message.type == "error":
            record.errors.append(f"console: {message.text}")

    async def on_response(response: Response) -> None:
        path = response.url.split("?")[0]
        if not response.ok or not path.endswith(("/api/session", "/api/shown")):
            return
        try:
            state = await response.json()
        except Exception:  # the page navigated away before the body was read
            return
        command = state.get("command")
        if state.get("phase") == "watch" and command:
            record.runs[int(command["index"])] = command["run"]

    # The operator's stop is a key press or a click sent by this script while the page
    # animates: one that reacts to the last moments of a run could reach the page after
    # that run has ended and the next has started. So while a stop is on its way, the
    # next run's POST /api/shown (whose reply starts the animation and enables Interrupt)
    # is held back: the stop lands on the run it was meant for, or on none.
    hold = asyncio.Event()
    hold.set()

    async def on_shown(route: Route) -> None:
        await hold.wait()
        await route.continue_()

    await page.route("**/api/shown", on_shown)
    page.on("console", on_console)
    page.on("pageerror", lambda e: record.errors.append(f"page error: {e}"))
    page.on("response", on_response)
    # Every page is loaded before the first run starts (less for the machine to do while
    # the operators watch); then they press Start one after the other.
    await open_consent(page, console, record)
    loaded.append(record.role.name)
    if len(loaded) == participants:
        first_turn.set()
    await turn.wait()
    try:
        await enroll(page, record)
    finally:
        next_turn.set()
    try:
        await session(page, record, hold)
    except Exception as e:
        where = "".join(traceback.format_exception(type(e), e, e.__traceback__)[-4:-1])
        page_now = await page.evaluate(PAGE_NOW)
        raise Failure(f"{type(e).__name__} {e} in\n{where}the page showing {page_now}") from e
    record.mouse_events = int(await page.evaluate("window.__mouse"))
    # Leaving the page (pagehide) sends the `left` beacon.
    await page.goto("about:blank")
    await page.close()


async def run_participants(console: Console, roles: List[Role], fail: List[str]) -> List[Record]:
    chromium = os.environ.get("TRUSTCBR_CHROMIUM", "/usr/bin/chromium")
    records = [Record(role) for role in roles]
    async with async_playwright() as p:
        browser = await p.chromium.launch(executable_path=chromium, args=CHROMIUM_ARGS)
        contexts = []
        for _ in roles:
            context = await browser.new_context(viewport={"width": 800, "height": 600})
            await context.add_init_script(COUNT_MOUSE)
            contexts.append(context)
        turns = [asyncio.Event() for _ in range(len(roles) + 1)]
        loaded: List[str] = []
        done = await asyncio.gather(
            *(
                participant(
                    contexts[i],
                    console,
                    records[i],
                    turns[i],
                    turns[i + 1],
                    loaded,
                    len(roles),
                    turns[0],
                )
                for i in range(len(roles))
            ),
            return_exceptions=True,
        )
        failed = [
            f"{record.role.name}: {type(e).__name__}: {e}"
            for record, e in zip(records, done)
            if isinstance(e, BaseException)
        ]
        if failed:
            raise Failure("; ".join(failed))
        for context in contexts:
            await context.close()
        # Once the four are done (so the overview lists them alone): the API's guards, then
        # a fifth participant's stop at the very end of a run.
        wait_for_left(console, records)
        check_api(console, records, fail)
        edge = await stop_at_the_end(browser, console)
        if edge:
            fail.append(edge)
        await browser.close()
    return records


# Holds the page's animation frames back while `window.__hold` is set: the page's clock
# and drawing stop where they are, and the run does not end by itself, as when a key
# press comes between the last frame of a run and the frame that would end it.
HOLD_FRAMES = """
window.__hold = false;
const frame = window.requestAnimationFrame.bind(window);
window.requestAnimationFrame = (cb) => frame((t) => { if (!window.__hold) cb(t); });
"""


async def stop_at_the_end(browser: Browser, console: Console) -> Optional[str]:
    """A participant presses the space bar after the run's last moment but before the page
    has ended it (the frames held back). The page then sends the run's duration, rounded to
    the millisecond: the stop must be stored (0 <= at_s <= duration_s), not refused. Plays
    the runs to their ends until one whose duration rounds up. Returns a failure, or None.
    """
    context = await browser.new_context(viewport={"width": 800, "height": 600})
    await context.add_init_script(HOLD_FRAMES)
    page = await context.new_page()
    try:
        await page.goto(console.url + "/")
        async with page.expect_response("**/api/participants") as enrolled:
            await page.click("#start")
        token = str((await (await enrolled.value).json())["token"])
        while True:
            step = await next_step(page, PATIENCE_S, resumed=True)
            if step["phase"] == "done":
                return "stop at the end: no run's duration rounds up to the next millisecond"
            if step["phase"] == "rate":
                await page.click("#rate-form label >> nth=0")
                await page.click("#rate-continue")
                await settle(
                    page,
                    "() => !document.querySelector('#rate-form input:checked') ||"
                    " document.getElementById('main').getAttribute('data-phase') !== 'rate'",
                    every_ms=20,
                )
                continue
            _, state = console.request("GET", "/api/session", token=token)
            k, run = state["command"]["index"], state["command"]["run"]
            duration = float(run["duration_s"])
            sent = math.floor(duration * 1000 + 0.5) / 1000  # the page's Math.round
            if sent <= duration:
                await settle(page, "() => document.getElementById('interrupt').disabled", None, 20)
                continue
            await page.evaluate("window.__hold = true")
            await asyncio.sleep(duration / SPEEDUP + 0.1)
            async with page.expect_response("**/api/stop"):
                await page.keyboard.press("Space")
            await settle(
                page,
                "(p) => document.getElementById('alert').textContent ||"
                " document.getElementById('main').getAttribute('data-phase') !== 'watch' ||"
                " document.getElementById('progress').textContent !== p",
                step["progress"],
                20,  # not at animation frames: they are held back
            )
            alert = await page.text_content("#alert")
            _, events = console.request(
                "GET", f"/api/admin/events?participant={state['participant']}", token=console.admin
            )
            stops = [e for e in events if e["kind"] == "stop" and e["command"] == k]
            if alert or not stops:
                return (
                    f"stop at the end: a key press after the run's end (duration_s {duration!r})"
                    f" made the page send at_s {sent} (its Math.round(t * 1000) / 1000 of the"
                    f" clamped run time); the server refused it: {alert!r}; the participant is"
                    " stuck (Retry repeats the refused request)"
                )
            return None
    except Exception as e:
        page_now = await page.evaluate(PAGE_NOW)
        return f"stop at the end: {type(e).__name__} {e}, the page showing {page_now}"
    finally:
        await context.close()


# ---------------------------------------------------------------------- the checks


def not_blank(png: bytes, path: Path, fail: List[str]) -> str:
    """Checks with .ci/png-not-blank.py that the screenshot `png` (written to `path`)
    shows something; returns what the script says of it."""
    path.write_bytes(png)
    checked = subprocess.run(
        [sys.executable, str(ROOT / ".ci/png-not-blank.py"), str(path)],
        capture_output=True,
        text=True,
    )
    # Its verdict, or the assertion that stopped it: the last line it wrote.
    lines = (checked.stdout + checked.stderr).strip().splitlines() or [""]
    said = lines[-1].replace(f"{path}: ", "")
    if checked.returncode != 0:
        fail.append(f"mid-run screenshot: {said}")
    return said


def by_command(events: List[Dict[str, Any]], kind: str) -> Dict[int, List[Dict[str, Any]]]:
    out: Dict[int, List[Dict[str, Any]]] = {}
    for e in events:
        if e["kind"] == kind:
            out.setdefault(int(e["command"]), []).append(e)
    return out


def check_events(
    record: Record, events: List[Dict[str, Any]], statements: bool, fail: List[str]
) -> None:
    """The kinds each participant must have, in order, for every command."""
    who = f"{record.pseudonym} ({record.role.name})"
    seqs = [e["seq"] for e in events]
    if seqs != list(range(len(events))):
        fail.append(f"{who}: seq is not 0..{len(events) - 1} in order: {seqs}")
    if not events or events[0]["kind"] != "enrolled":
        fail.append(f"{who}: the first event is not `enrolled`")
    decisions = by_command(events, "decision")
    commands = len(decisions)
    if sorted(decisions) != list(range(commands)) or commands == 0:
        fail.append(f"{who}: decisions for commands {sorted(decisions)}")
    shown, stops, ends = (by_command(events, k) for k in ("shown", "stop", "end"))
    said, resumed = by_command(events, "statement"), by_command(events, "resumed")
    for k in range(commands):
        if len(decisions.get(k, [])) != 1:
            fail.append(f"{who}: command {k} has {len(decisions.get(k, []))} decisions")
        if len(shown.get(k, [])) != 1:
            fail.append(f"{who}: command {k} has {len(shown.get(k, []))} `shown` events")
        closes = len(stops.get(k, [])) + len(ends.get(k, []))
        if closes != 1:
            fail.append(f"{who}: command {k} has {closes} stop/end events, not 1")
        wanted = 1 if statements and k in stops else 0
        if len(said.get(k, [])) != wanted:
            fail.append(f"{who}: command {k} has {len(said.get(k, []))} statements, not {wanted}")
    # Each command's own events in order, and the last one ends the episode.
    for k in range(commands):
        order = [
            e["kind"]
            for e in events
            if e.get("command") == k
            and e["kind"] in ("shown", "stop", "statement", "end", "decision")
        ]
        allowed = [["shown", "end", "decision"]]
        allowed.append(
            ["shown", "stop", "statement", "decision"]
            if statements
            else ["shown", "stop", "decision"]
        )
        if order not in allowed:
            fail.append(f"{who}: command {k}'s events in the order {order}")
    if commands:
        last = decisions[commands - 1][0]
        if last["reply"].get("ok") != "settled" and last.get("abandon_reply") is None:
            fail.append(f"{who}: the last decision {last['reply'].get('ok')} ends no episode")
    # The ratings: one per behavior ended (a decision other than keep), in order.
    owed = [
        k
        for k in range(commands)
        if decisions[k][0]["reply"].get("ok") != "keep"
        or decisions[k][0].get("abandon_reply") is not None
    ]
    ratings = [e for e in events if e["kind"] == "rating"]
    if [r["after_command"] for r in ratings] != owed:
        fail.append(f"{who}: ratings after {[r['after_command'] for r in ratings]}, owed {owed}")
    if [r["number"] for r in ratings] != list(range(len(ratings))):
        fail.append(f"{who}: rating numbers {[r['number'] for r in ratings]}")
    for r in ratings:
        d = decisions[int(r["after_command"])][0]
        given_up = d["reply"].get("ok") == "switch" and d.get("abandon_reply") is None
        if r["value"] != (2 if given_up else 6):
            fail.append(f"{who}: rating {r['number']} is {r['value']} after {d['reply'].get('ok')}")
    # A `left` for each reload and one at the end; a `resumed` for each reload after which
    # the page shows a run it had shown before.
    left = [e["seq"] for e in events if e["kind"] == "left"]
    if not events or events[-1]["kind"] != "left":
        fail.append(f"{who}: the last event is not `left` (the page was left after the end)")
    if len(left) != 1 + len(record.reloads):
        fail.append(f"{who}: {len(left)} `left` events, {len(record.reloads)} reloads")
    want_resumed = [
        after
        for (_, after), seq in zip(record.reloads, left)
        if after is not None and any(shown_at["seq"] < seq for shown_at in shown.get(after, []))
    ]
    got_resumed = sorted(k for k, v in resumed.items() for _ in v)
    if got_resumed != sorted(want_resumed):
        fail.append(f"{who}: `resumed` for commands {got_resumed}, expected {want_resumed}")
    if record.role.reload and record.reloaded_at is not None:
        k = record.reloaded_at
        order = [
            e["kind"]
            for e in events
            if e.get("command") == k and e["kind"] in ("shown", "resumed", "stop", "end")
        ]
        if order[:2] != ["shown", "resumed"]:
            fail.append(f"{who}: command {k}'s events around the reload: {order}")


def check_stops(
    record: Record, events: List[Dict[str, Any]], statements: bool, fail: List[str]
) -> List[float]:
    """Each command closed where the scripted operator would close it; returns each stop's
    lag (run s) behind what the operator reacted to."""
    who = f"{record.pseudonym} ({record.role.name})"
    stops = {int(e["command"]): float(e["at_s"]) for e in events if e["kind"] == "stop"}
    ends = {int(e["command"]) for e in events if e["kind"] == "end"}
    said = {int(e["command"]): e["cause"] for e in events if e["kind"] == "statement"}
    lags = []
    for k in sorted(stops.keys() | ends):
        if record.reactions.get(k) == "reload":
            # Closed by the page while the operator's reload was on its way (see
            # `reload_mid_run`): nobody pressed anything, so the run played to its end.
            if k in stops:
                fail.append(
                    f"{who}: command {k} stopped at {stops[k]:.3f} s, while the operator was"
                    " reloading the page (it pressed nothing)"
                )
            continue
        run = record.runs.get(k)
        if run is None:
            fail.append(f"{who}: the page never got command {k}'s run")
            continue
        duration = float(run["duration_s"])
        hits = [float(e["t"]) for e in run["events"] if e["kind"] == "collision"]
        collision = min(hits) if hits else float("inf")
        trigger = min(collision, DEADLINE_SEEN_S)
        cause = "collision" if collision <= DEADLINE_SEEN_S else "deadline"
        # Both shown in the same frame: the operator may name either.
        causes = {cause}
        if abs(collision - DEADLINE_SEEN_S) <= FRAME_S:
            causes = {"collision", "deadline"}
        if k in stops:
            at = stops[k]
            if trigger > duration:
                fail.append(f"{who}: command {k} stopped at {at} s, but nothing called for it")
            elif not trigger - CLOCK_SLACK_S <= at <= trigger + STOP_TOLERANCE_S:
                fail.append(
                    f"{who}: command {k} stopped at {at:.3f} s; the operator reacts to the"
                    f" {cause} at {trigger:.3f} s (+{STOP_TOLERANCE_S:.0f} s allowed)"
                )
            else:
                lags.append(at - trigger)
            if statements and said.get(k) not in causes:
                fail.append(f"{who}: command {k}'s stated cause {said.get(k)!r}, not {cause!r}")
        elif trigger <= duration - STOP_TOLERANCE_S:
            fail.append(
                f"{who}: command {k} played to its end at {duration:.1f} s, but the operator"
                f" reacts to the {cause} at {trigger:.3f} s"
            )
        elif trigger <= duration - FRAME_S and record.reactions.get(k) not in CAUSE_TEXT:
            # Shown at least a frame before the end: the operator must have pressed, too
            # late (the run ended before the press reached the page).
            fail.append(
                f"{who}: command {k}: the page showed the {cause} at {trigger:.3f} s, before"
                f" the run's end at {duration:.3f} s, and the operator did not react"
            )
    return lags


def check_adapter(
    binary: str, record: Record, events: List[Dict[str, Any]], folder: Path, fail: List[str]
) -> int:
    """Replays the participant's outcome reports into `trustcbr serve` with their arm and
    seed; every reply must equal the recorded one. Returns the replies compared."""
    who = f"{record.pseudonym} ({record.role.name})"
    enrolled = events[0]
    cases = folder / f"cases-{record.pseudonym}.db"
    serve = subprocess.Popen(
        [binary, "serve", "--domain", "movement", "--cases", str(cases)]
        + ["--arm", str(enrolled["arm"]), "--seed", str(enrolled["seed"])],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    assert serve.stdin is not None and serve.stdout is not None

    def ask(request: Any) -> Any:
        assert serve.stdin is not None and serve.stdout is not None
        serve.stdin.write(json.dumps(request).encode() + b"\n")
        serve.stdin.flush()
        line = serve.stdout.readline()
        if not line:
            raise Failure(
                f"{who}: serve ended: {serve.stderr.read().decode() if serve.stderr else ''}"
            )
        return json.loads(line)

    compared = 0
    try:
        begun = ask({"request": "begin"})
        if "error" in begun:
            fail.append(f"{who}: serve refused begin: {begun}")
            return 0
        for d in (e for e in events if e["kind"] == "decision"):
            reply = ask(d["report"])
            compared += 1
            if reply != d["reply"]:
                fail.append(
                    f"{who}: command {d['command']}: serve replies {reply}, recorded {d['reply']}"
                )
                break
            if d.get("abandon_reply") is not None:
                abandoned = ask({"request": "abandon"})
                compared += 1
                if abandoned != d["abandon_reply"]:
                    fail.append(
                        f"{who}: command {d['command']}: serve's abandon reply {abandoned},"
                        f" recorded {d['abandon_reply']}"
                    )
    finally:
        serve.stdin.close()
        serve.wait(30)
    return compared


def check_api(console: Console, records: List[Record], fail: List[str]) -> None:
    """Tokens are isolated; the admin API needs the admin token."""
    for r in records:
        status, state = console.request("GET", "/api/session", token=r.token)
        if status != 200 or state.get("participant") != r.pseudonym:
            fail.append(
                f"{r.role.name}: its token gives {status} {state and state.get('participant')}"
            )
        elif state.get("phase") != "done":
            fail.append(f"{r.pseudonym}: phase {state.get('phase')} after the session, not done")
    status, _ = console.request("GET", "/api/session", token=secrets.token_hex(16))
    if status != 401:
        fail.append(f"GET /api/session with an unknown token: {status}, not 401")
    status, _ = console.request("POST", "/api/stop", {"command": 0, "at_s": 1.0})
    if status != 401:
        fail.append(f"POST /api/stop without a token: {status}, not 401")
    for token in (None, "not-the-admin-token", records[0].token):
        status, _ = console.request("GET", "/api/admin/participants", token=token)
        if status != 401:
            fail.append(f"GET /api/admin/participants with token {token!r}: {status}, not 401")
    status, rows = console.request("GET", "/api/admin/participants", token=console.admin)
    names = sorted(row["participant"] for row in rows or [])
    if status != 200 or names != sorted(r.pseudonym for r in records):
        fail.append(f"GET /api/admin/participants with the admin token: {status} {names}")
    elif any(row["phase"] != "done" for row in rows):
        fail.append(f"admin overview: phases {[row['phase'] for row in rows]}")


def wait_for_left(console: Console, records: List[Record]) -> None:
    """The `left` beacons are sent as the pages go: waits (a few seconds at most) until the
    server has stored each participant's last."""
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:
        pending = 0
        for r in records:
            _, events = console.request(
                "GET", f"/api/admin/events?participant={r.pseudonym}", token=console.admin
            )
            if not events or events[-1]["kind"] != "left":
                pending += 1
        if not pending:
            return
        time.sleep(0.1)


def main() -> int:
    started = time.monotonic()
    binary = os.environ.get("TRUSTCBR_BIN", str(ROOT / "target/debug/trustcbr"))
    roles = [
        Role("keyboard-1", keyboard=True),
        Role("keyboard-2", keyboard=True),
        Role("mouse-reload", keyboard=False, reload=True),
        Role("mouse", keyboard=False),
    ]
    fail: List[str] = []
    with tempfile.TemporaryDirectory(prefix="console-study-") as scratch:
        folder = Path(scratch)
        console = Console(binary, STUDY, folder)
        try:
            records = asyncio.run(run_participants(console, roles, fail))
        finally:
            console.stop()
        out = folder / "export"
        lines = console.export_events(out)
        keep = os.environ.get("CONSOLE_STUDY_KEEP")
        if keep:
            shutil.copytree(out, keep, dirs_exist_ok=True)
            (Path(keep) / "console.stderr").write_text(console.stderr_text())
        server_errors = [line for line in console.stderr_text().splitlines() if "console:" in line]
        fail += [f"server: {line}" for line in server_errors]
        lags: List[float] = []
        replies = 0
        conditions: Dict[str, str] = {}
        for r in records:
            events = sorted(
                (e for e in lines if e["participant"] == r.pseudonym), key=lambda e: e["seq"]
            )
            if not events:
                fail.append(f"{r.pseudonym} ({r.role.name}): no events exported")
                continue
            condition = str(events[0].get("condition"))
            conditions[r.pseudonym] = condition
            statements = STATEMENTS.get(condition, False)
            check_events(r, events, statements, fail)
            lags += check_stops(r, events, statements, fail)
            replies += check_adapter(binary, r, events, folder, fail)
            had_explanation = any(
                isinstance(e["reply"].get("explanation"), dict)
                and e["reply"]["explanation"].get("sentence")
                for e in events
                if e["kind"] == "decision"
            )
            if condition == "silent" and r.explanations:
                fail.append(f"{r.pseudonym}: the silent condition showed {r.explanations[0]!r}")
            if condition == "explained" and had_explanation and not r.explanations:
                fail.append(f"{r.pseudonym}: the explained condition never showed an explanation")
            fail += [f"{r.pseudonym} ({r.role.name}): {e}" for e in r.errors + r.wide]
            if r.role.keyboard and r.mouse_events:
                fail.append(
                    f"{r.pseudonym}: keyboard participant's page saw {r.mouse_events} mouse events"
                )
            if not r.role.keyboard and not r.mouse_events:
                fail.append(f"{r.pseudonym}: the mouse counter saw no click (it does not work)")
            if r.role.reload and r.reloaded_at is None:
                fail.append(
                    f"{r.pseudonym}: none of its {len(r.reloads)} reloads reached the page before"
                    " the run's end"
                    if r.reloads
                    else f"{r.pseudonym}: no run was long enough to reload in the middle"
                )
        if sorted(conditions.values()) != ["explained", "explained", "silent", "silent"]:
            fail.append(f"conditions {conditions}: not two of each")
        shot = next((r.screenshot for r in records if r.screenshot), b"")
        shown = ""
        if not shot:
            fail.append("no mid-run screenshot was taken")
        else:
            shown = not_blank(shot, folder / "mid-run.png", fail)
    if fail:
        print("console browser test FAILED:", file=sys.stderr)
        for line in fail:
            print(f"  {line}", file=sys.stderr)
        return 1
    who = ", ".join(f"{r.pseudonym} {conditions[r.pseudonym]} {r.role.name}" for r in records)
    print(
        f"console browser test: 4 participants ({who}),"
        f" {sum(1 for e in lines if e['participant'] in conditions)} events,"
        f" {sum(len(r.runs) for r in records)} runs, {len(lags)} stops"
        f" ({min(lags, default=0):.1f} to {max(lags, default=0):.1f} run s after what they"
        f" react to, {STOP_TOLERANCE_S:.0f} allowed), {replies} adapter replies equal to serve's,"
        f" a stop after a run's end stored, screenshot {shown}, no console error,"
        f" in {time.monotonic() - started:.0f} s"
    )
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (Failure, ConsoleStartError) as e:
        print(f"console browser test FAILED: {e}", file=sys.stderr)
        sys.exit(1)
