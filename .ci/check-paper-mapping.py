#!/usr/bin/env python3
"""Checks that docs/paper-mapping.md's line references point at what they name (CI: .ci/test-all).

Usage: check-paper-mapping.py [PAGE.md]   (default: docs/paper-mapping.md)

The page maps the paper to the code and cites source lines as `FILE:LINE` or
`FILE:FIRST-LAST`. Code moves, and a stale line number sends the reader to the wrong place
without anyone noticing; so each reference must name, in backticks in the same table cell
(or, in prose, the same paragraph or list item), an identifier that is on the line it
cites, and this script checks that it does. For every reference:
- the file exists. A path with a folder is read from the repository's root; a bare file
  name (`adapter.rs:525`) is the last path on the page before it that ends in that name
  (`trust/src/adapter.rs`), else the one file of that name in the repository;
- the line exists (for a range, both ends, in order);
- the line (for a range, its first line, where what it names begins) is not a `//`
  comment and holds, as a whole word, at least one identifier quoted in the cell or
  paragraph. A quote's identifiers are its word tokens of two characters or more, less
  Rust keywords, less the qualifiers before `::` and less the parts of kebab-case names:
  `trust::Thresholds::verdict` is `verdict`, `lab::seeds::{stream, stream_seed}` is
  `stream` and `stream_seed`, and `e_past.iter().any(...)` is `e_past`, `iter` and `any`.
  Quotes that are references or file paths name nothing.

Prints each failure as `PAGE:LINE: FILE:N does not contain any of [...]` (or why the file
or the line is missing) and exits 1 if there is one; otherwise prints `N references
checked`. Python 3 standard library only.
"""

from __future__ import annotations

import os
import re
import sys
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
DEFAULT_PAGE = REPO / "docs" / "paper-mapping.md"
# Folders never searched for a bare file name (nor hidden ones): build output, environments.
SKIPPED_FOLDERS = {"target", "node_modules", "__pycache__", "venv"}

REFERENCE = re.compile(
    r"(?<![\w./-])(?P<path>[\w.-]+(?:/[\w.-]+)*\.[A-Za-z]\w*)"
    r":(?P<first>\d+)(?:-(?P<last>\d+))?(?![\w.])"
)
FULL_PATH = re.compile(r"[\w.-]+(?:/[\w.-]+)+")
CODE_SPAN = re.compile(r"`([^`]+)`")
FILE_PATH = re.compile(r"[\w./-]*(?:/|\.(?:rs|ron|md|toml|json|py|svg|csv|sh))[\w./-]*")
TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
LIST_ITEM = re.compile(r"([-*+]|\d+\.)\s")
RUST_KEYWORDS = frozenset(
    "as break const continue crate dyn else enum false fn for if impl in let loop match mod "
    "move mut pub ref return self Self static struct super trait true type use where while "
    "Some None Ok Err".split()
)


@dataclass(frozen=True)
class Unit:
    """A table cell, or a paragraph or list item of prose: the text a reference's names are
    read from, and where it lies (lines `first` to `last`, and within a table row the
    columns `start` to `end` of the raw line)."""

    first: int
    last: int
    start: int
    end: int
    text: str

    def holds(self, line: int, column: int) -> bool:
        """Whether the page's text at `line`, `column` is in this unit."""
        return self.first <= line <= self.last and self.start <= column < self.end


@dataclass(frozen=True)
class Reference:
    """One `FILE:LINE` or `FILE:FIRST-LAST` on the page, where it is written."""

    line: int
    column: int
    written: str
    path: str
    first: int
    last: int

    def cited(self, path: str) -> str:
        """The reference as `path:LINE` or `path:FIRST-LAST`."""
        lines = f"{self.first}-{self.last}" if self.last != self.first else f"{self.first}"
        return f"{path}:{lines}"


def cells(number: int, row: str) -> list[Unit]:
    """The cells of a Markdown table row; `\\|` is a bar within a cell, as on GitHub."""
    bars = [m.start() for m in re.finditer(r"(?<!\\)\|", row)]
    if not row.rstrip().endswith("|"):
        bars.append(len(row))
    return [
        Unit(number, number, start + 1, end, row[start + 1 : end].replace("\\|", "|"))
        for start, end in zip(bars, bars[1:])
    ]


def units(lines: list[str]) -> list[Unit]:
    """The page's table cells and paragraphs (list items apart), outside code blocks."""
    found: list[Unit] = []
    paragraph: list[tuple[int, str]] = []
    in_fence = False

    def close() -> None:
        if paragraph:
            text = " ".join(line for _, line in paragraph)
            found.append(Unit(paragraph[0][0], paragraph[-1][0], 0, sys.maxsize, text))
            paragraph.clear()

    for number, line in enumerate(lines, start=1):
        stripped = line.strip()
        if stripped.startswith("```"):
            close()
            in_fence = not in_fence
        elif in_fence:
            continue
        elif not stripped or stripped.startswith("#"):
            close()
        elif stripped.startswith("|"):
            close()
            found.extend(cells(number, line))
        else:
            if LIST_ITEM.match(stripped):
                close()
            paragraph.append((number, stripped))
    close()
    return found


def identifiers(text: str) -> list[str]:
    """The identifiers `text` quotes in backticks, in order, each once."""
    names: list[str] = []
    for quote in CODE_SPAN.findall(text):
        quote = quote.strip()
        if REFERENCE.fullmatch(quote) or FILE_PATH.fullmatch(quote):
            continue
        for m in TOKEN.finditer(quote):
            token = m.group(0)
            qualifier = quote.startswith("::", m.end())
            after, before = quote[m.end() :], quote[: m.start()]
            kebab = re.match(r"-[A-Za-z]", after) or re.search(r"[A-Za-z0-9]-$", before)
            short = len(token) < 2 or token in RUST_KEYWORDS
            if not (qualifier or kebab or short or token in names):
                names.append(token)
    return names


def repository_files(root: Path) -> dict[str, list[str]]:
    """Every file of the repository by its name, as paths from the root."""
    by_name: dict[str, list[str]] = {}
    for folder, subfolders, files in os.walk(root):
        subfolders[:] = sorted(
            d for d in subfolders if d not in SKIPPED_FOLDERS and not d.startswith(".")
        )
        for name in files:
            path = Path(folder, name).relative_to(root).as_posix()
            by_name.setdefault(name, []).append(path)
    return by_name


def resolve(name: str, earlier: list[str], by_name: dict[str, list[str]]) -> str:
    """The path from the root of the file a reference writes as `name`, or an error."""
    if "/" in name:
        return name
    for path in reversed(earlier):
        if path.rsplit("/", 1)[-1] == name:
            return path
    candidates = sorted(by_name.get(name, []))
    if len(candidates) == 1:
        return candidates[0]
    if not candidates:
        raise LookupError(f"{name}: no file of that name in the repository")
    listed = ", ".join(candidates)
    raise LookupError(f"{name}: no path before it on the page ends in it; it could be {listed}")


def contains(line: str, name: str) -> bool:
    """Whether `name` is on `line` as a whole identifier."""
    return re.search(rf"(?<![A-Za-z0-9_]){re.escape(name)}(?![A-Za-z0-9_])", line) is not None


def check(page: Path, shown: str, root: Path) -> tuple[int, list[str]]:
    """The number of references on `page` and a message for each that fails."""
    lines = page.read_text(encoding="utf-8").splitlines()
    page_units = units(lines)
    by_name = repository_files(root)
    # Paths with a folder, where the page writes them: what a bare file name refers to.
    full_paths = [
        (number, m.start(), m.group(0))
        for number, line in enumerate(lines, start=1)
        for m in FULL_PATH.finditer(line)
    ]
    sources: dict[str, list[str] | None] = {}
    count = 0
    failures: list[str] = []
    for number, line in enumerate(lines, start=1):
        for m in REFERENCE.finditer(line):
            unit = next((u for u in page_units if u.holds(number, m.start())), None)
            if unit is None:  # in a code block or a heading: not a reference the page makes
                continue
            count += 1
            reference = Reference(
                line=number,
                column=m.start(),
                written=m.group(0),
                path=m.group("path"),
                first=int(m.group("first")),
                last=int(m.group("last") or m.group("first")),
            )
            failure = check_one(reference, unit, full_paths, by_name, sources, root)
            if failure:
                failures.append(f"{shown}:{number}: {failure}")
    return count, failures


def check_one(
    reference: Reference,
    unit: Unit,
    full_paths: list[tuple[int, int, str]],
    by_name: dict[str, list[str]],
    sources: dict[str, list[str] | None],
    root: Path,
) -> str | None:
    """Why `reference` fails, or `None` when it points at a name its unit quotes."""
    here = (reference.line, reference.column)
    earlier = [path for line, column, path in full_paths if (line, column) < here]
    try:
        path = resolve(reference.path, earlier, by_name)
    except LookupError as e:
        return f"{reference.written}: {e}"
    if path not in sources:
        file = root / path
        sources[path] = file.read_text(encoding="utf-8").splitlines() if file.is_file() else None
    source = sources[path]
    if source is None:
        return f"{reference.written}: {path} does not exist"
    cited = reference.cited(path)
    if not 1 <= reference.first <= reference.last <= len(source):
        return f"{cited} is not a line range of {path} ({len(source)} lines)"
    names = identifiers(unit.text)
    if not names:
        return f"{cited}: its cell or paragraph quotes no identifier to look for"
    line = source[reference.first - 1]
    if not line.lstrip().startswith("//") and any(contains(line, name) for name in names):
        return None
    return f"{cited} does not contain any of {names}"


def main(arguments: list[str]) -> int:
    if len(arguments) > 1 or arguments[:1] in (["-h"], ["--help"]):
        print("usage: check-paper-mapping.py [PAGE.md]", file=sys.stderr)
        return 2
    page = Path(arguments[0]) if arguments else DEFAULT_PAGE
    shown = arguments[0] if arguments else DEFAULT_PAGE.relative_to(REPO).as_posix()
    count, failures = check(page, shown, REPO)
    for failure in failures:
        print(failure)
    if failures:
        print(f"{len(failures)} of {count} references do not point at what they name")
        return 1
    print(f"{count} references checked")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
