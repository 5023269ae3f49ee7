#!/usr/bin/env python3
"""Runs every code block of README.md and docs/*.md as written (CI: .ci/test-all).

Usage: check-docs.py [FILE.md ...]   (default: README.md and docs/*.md)

Environment: TRUSTCBR_BIN, the `trustcbr` binary the shell blocks call (CI: the debug
build `cargo test` made); the Python running this script is the one whose environment has
the package installed (CI: the virtual environment .ci/test-all builds).

What runs, by the fence's language (its first word):
- `python`: every block of a page, in order, in one interpreter session (a page is read
  top to bottom: a later block may use what an earlier one defined), in an empty scratch
  folder (the blocks must run from any working directory);
- `sh`, `bash`, `console`: each block with `bash -e -o pipefail` (a `console` block's
  commands are its lines starting with `$ `), in a scratch folder that mirrors the
  repository's root (a symlink per entry but those git ignores), so paths the text gives
  from the root work and what the commands write stays out of the checkout. `cargo run
  --release --` and `target/release/trustcbr` are run as `trustcbr`, the binary CI built
  from the same source (a release build would cost CI minutes for the same code), and a
  `cargo build --release` line is skipped for that reason;
- `rust`: compiled and run as doctests: the page must be included in src/lib.rs with
  `#[doc = include_str!(...)]` (`cargo test` runs them); this script checks it is;
- anything else (`json`, `text`, `ron`, `toml`, none) is data or output, not run.

Attributes after the language word change that, each `key=value` (quote a value with
spaces, shell-style), and are invisible when the Markdown is rendered; on a page rustdoc
renders (docs/plugin-guide.md, docs/protocol.md), whose fences may not hold `=`, they
stand in a comment on the line before the fence instead: `<!-- check-docs: no-run="REASON" -->`:
- `no-run="REASON"`: not run; the reason is printed. Kept for blocks that need what CI
  does not have (a fleet's hosts, a Slurm cluster) or that CI runs elsewhere;
- `replace="OLD => NEW"` (repeatable): run with OLD replaced by NEW, for a smaller size
  of a long command (`--trials 500 => --trials 20`); OLD must occur in the block;
- `cwd=repo`: a Python block runs in the mirrored repository root instead;
- `before="COMMAND"`: a Python block whose text asks the reader to run a command first
  (a report to read, say) has that command run, as a shell block would be, in the
  block's working directory before the page's Python session starts.

Prints one line per block and `docs: N passed, N failed, N skipped`; exits 1 on a failure.
"""

from __future__ import annotations

import json
import os
import re
import shlex
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional

REPO = Path(__file__).resolve().parent.parent
RUN_LANGUAGES = {"python", "sh", "bash", "console", "rust"}
COMMENT_START = "<!-- check-docs:"
TIMEOUT_S = 600
# The release binary of the text is the binary CI built (see the module's doc).
SHELL_REWRITES = [
    (re.compile(r"cargo run --release -- "), "trustcbr "),
    (re.compile(r"target/release/trustcbr\b"), "trustcbr"),
    (
        re.compile(r"^cargo build --release\s*$", re.M),
        ": cargo build --release, skipped: the binary CI built is used",
    ),
]


@dataclass
class Block:
    path: Path
    line: int
    language: str
    code: str
    attributes: Dict[str, str] = field(default_factory=dict)
    replacements: List[List[str]] = field(default_factory=list)

    @property
    def where(self) -> str:
        return f"{self.path.relative_to(REPO)}:{self.line}"


def blocks_of(path: Path) -> List[Block]:
    found: List[Block] = []
    lines = path.read_text(encoding="utf-8").splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("```"):
            info = line[3:].strip()
            words = shlex.split(info) if info else []
            language = words[0].split(",")[0] if words else ""
            block = Block(path, i + 1, language, "")
            # Attributes may also stand in an HTML comment on the line before the fence
            # (`<!-- check-docs: no-run="..." -->`), for a page rustdoc renders: rustdoc
            # refuses `key=value` words in a fence.
            previous = lines[i - 1].strip() if i > 0 else ""
            if previous.startswith(COMMENT_START) and previous.endswith("-->"):
                words += shlex.split(previous[len(COMMENT_START) : -len("-->")])
            for word in words[1:]:
                key, _, value = word.partition("=")
                if key == "replace":
                    old, sep, new = value.partition(" => ")
                    if not sep:
                        raise SystemExit(f'{block.where}: replace="OLD => NEW", got {value!r}')
                    block.replacements.append([old, new])
                else:
                    block.attributes[key] = value
            body = []
            i += 1
            while i < len(lines) and not lines[i].startswith("```"):
                body.append(lines[i])
                i += 1
            block.code = "\n".join(body) + "\n"
            found.append(block)
        i += 1
    return found


def prepared(block: Block) -> str:
    code = block.code
    for old, new in block.replacements:
        if old not in code:
            raise ValueError(f"replace: `{old}` does not occur in the block")
        code = code.replace(old, new)
    return code


def mirror_of_repo(root: Path) -> None:
    """Fills `root` with a symlink to each entry of the repository's root, but those git
    ignores: what a reader's own runs left there (`results/` of the README's first
    command, build folders) is not the repository, and a block writing to the same place
    must find it free."""
    entries = [e for e in REPO.iterdir() if e.name != ".git"]
    ignored = subprocess.run(
        ["git", "-C", str(REPO), "check-ignore", "--stdin"],
        input="\n".join(e.name for e in entries),
        capture_output=True,
        text=True,
    ).stdout.split("\n")
    for entry in entries:
        if entry.name not in ignored and entry.name != "target":
            (root / entry.name).symlink_to(entry)


def environment() -> Dict[str, str]:
    env = dict(os.environ)
    paths = [str(Path(sys.executable).parent)]
    binary = os.environ.get("TRUSTCBR_BIN")
    if binary:
        paths.insert(0, str(Path(binary).resolve().parent))
    env["PATH"] = os.pathsep.join(paths + [env.get("PATH", "")])
    env.setdefault("PYTHONUNBUFFERED", "1")
    return env


# How long each block that passed took (s), printed beside it: CI's time budget is spent
# here, and a slow example shows.
SECONDS_TAKEN: Dict[str, float] = {}


def run_shell(block: Block, cwd: Path) -> Optional[str]:
    started = time.monotonic()
    code = prepared(block)
    if block.language == "console":
        code = "\n".join(line[2:] for line in code.splitlines() if line.startswith("$ ")) + "\n"
    for pattern, replacement in SHELL_REWRITES:
        code = pattern.sub(replacement, code)
    ran = subprocess.run(
        ["bash", "-e", "-o", "pipefail", "-c", code],
        cwd=cwd,
        env=environment(),
        capture_output=True,
        text=True,
        timeout=TIMEOUT_S,
    )
    if ran.returncode != 0:
        return f"exit {ran.returncode}\n{ran.stdout[-2000:]}{ran.stderr[-3000:]}"
    SECONDS_TAKEN[block.where] = time.monotonic() - started
    return None


# Runs a page's Python blocks in one namespace; stops at the first failure, naming it.
SESSION = r"""
import json, sys, time, traceback
blocks = json.load(open(sys.argv[1]))
namespace = {"__name__": "__main__"}
for where, code in blocks:
    started = time.monotonic()
    try:
        exec(compile(code, where, "exec"), namespace)
    except BaseException:
        print(f"FAILED {where}", flush=True)
        traceback.print_exc()
        sys.exit(1)
    print(f"took {time.monotonic() - started:.1f} {where}", flush=True)
    print(f"ok {where}", flush=True)
"""


def run_python(blocks: List[Block], cwd: Path) -> Dict[str, Optional[str]]:
    for block in blocks:
        command = block.attributes.get("before")
        if command:
            problem = run_shell(Block(block.path, block.line, "sh", command + "\n"), cwd)
            if problem is not None:
                return {b.where: f"before: {problem}" for b in blocks}
    payload = [(b.where, prepared(b)) for b in blocks]
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump(payload, f)
    ran = subprocess.run(
        [sys.executable, "-c", SESSION, f.name],
        cwd=cwd,
        env=environment(),
        capture_output=True,
        text=True,
        timeout=TIMEOUT_S,
    )
    os.unlink(f.name)
    results: Dict[str, Optional[str]] = {}
    for line in ran.stdout.splitlines():
        if line.startswith("took "):
            seconds, where = line[5:].split(" ", 1)
            SECONDS_TAKEN[where] = float(seconds)
        elif line.startswith("ok "):
            results[line[3:]] = None
        elif line.startswith("FAILED "):
            results[line[7:]] = ran.stderr[-3000:]
    for b in blocks:
        results.setdefault(b.where, "not reached (an earlier block of the page failed)")
    return results


@dataclass
class PageResult:
    """What checking one page printed, and its counts."""

    lines: List[str] = field(default_factory=list)
    passed: int = 0
    failed: int = 0
    skipped: int = 0


def check_page(path: Path, lib: str) -> PageResult:
    """Runs every runnable block of `path` in a scratch folder of its own, so that pages
    are independent of each other and may be checked side by side."""
    result = PageResult()

    def report(block: Block, problem: Optional[str]) -> None:
        if problem is None:
            result.passed += 1
            taken = SECONDS_TAKEN.get(block.where)
            timing = "" if taken is None else f", {taken:.1f} s"
            result.lines.append(f"ok      {block.where} ({block.language}{timing})")
        else:
            result.failed += 1
            result.lines.append(f"FAILED  {block.where} ({block.language}): {problem}")

    blocks = [b for b in blocks_of(path) if b.language in RUN_LANGUAGES]
    runnable = []
    for block in blocks:
        reason = block.attributes.get("no-run")
        if reason is not None:
            if not reason.strip():
                report(block, "no-run needs a reason")
                continue
            result.skipped += 1
            result.lines.append(f"skipped {block.where} ({block.language}): {reason}")
        else:
            runnable.append(block)
    rust = [b for b in runnable if b.language == "rust"]
    if rust:
        included = f'include_str!("../{path.relative_to(REPO)}")' in lib
        for block in rust:
            report(
                block,
                None if included else "the page is not a doctest: include it in src/lib.rs",
            )
    with tempfile.TemporaryDirectory(prefix="trustcbr-docs-") as scratch:
        empty = Path(scratch) / "empty"
        empty.mkdir()
        mirror = Path(scratch) / "repo"
        mirror.mkdir()
        mirror_of_repo(mirror)
        python = [b for b in runnable if b.language == "python"]
        if python:
            # One session per working directory a page asks for.
            for cwd, group in (
                (empty, [b for b in python if b.attributes.get("cwd") != "repo"]),
                (mirror, [b for b in python if b.attributes.get("cwd") == "repo"]),
            ):
                if group:
                    try:
                        results = run_python(group, cwd)
                    except (ValueError, subprocess.TimeoutExpired) as e:
                        results = {b.where: str(e) for b in group}
                    for b in group:
                        report(b, results[b.where])
        for block in runnable:
            if block.language in {"sh", "bash", "console"}:
                try:
                    report(block, run_shell(block, mirror))
                except (ValueError, subprocess.TimeoutExpired) as e:
                    report(block, str(e))
    return result


def main() -> int:
    files = [Path(a).resolve() for a in sys.argv[1:]] or [REPO / "README.md"] + sorted(
        (REPO / "docs").glob("*.md")
    )
    lib = (REPO / "src" / "lib.rs").read_text(encoding="utf-8")
    # Pages side by side, one per core: each runs in its own scratch folder, and its lines
    # are printed whole, in the pages' order.
    with ThreadPoolExecutor(max_workers=os.cpu_count() or 1) as pool:
        pages = list(pool.map(lambda path: check_page(path, lib), files))
    for page in pages:
        for line in page.lines:
            print(line)
    passed = sum(p.passed for p in pages)
    failed = sum(p.failed for p in pages)
    skipped = sum(p.skipped for p in pages)
    print(f"docs: {passed} passed, {failed} failed, {skipped} skipped")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
