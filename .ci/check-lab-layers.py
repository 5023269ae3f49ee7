#!/usr/bin/env python3
"""Checks that the `lab` crate's imports run one way (docs/ARCHITECTURE.md, "The lab").

Every module of lab/src is a node; a `crate::...` path in its code (not its comments, not
its `#[cfg(test)]` tests) is an edge to the module that defines the item, following the
`pub use` re-exports of lib.rs and the folders' mod.rs. The check fails when
- two modules import each other, directly or round a loop, or
- a module imports from a folder listed after its own in FOLDERS, or a shared module at
  the crate's root imports from a folder, or
- a source file holds more than MAX_FILE_LINES lines before its tests, or a function is
  longer than MAX_FN_LINES lines.
Prints each offending import with its file and line. Run from the repository's root.
"""

import re
import sys
from collections.abc import Iterator
from pathlib import Path

Module = tuple[str, ...]

ROOT = Path("lab/src")
# The folders, lowest first: a module imports only from the root's shared modules, its
# own folder and the folders before it.
FOLDERS = ["contract", "reference", "experiment", "population", "report", "mission"]
MAX_FILE_LINES = 800
MAX_FN_LINES = 150
# Root modules that may import from folders: the conformance kit runs over the contract.
ROOT_CONSUMERS = {"testing"}
ITEM = re.compile(
    r"^\s*pub(?:\([a-z]+\))?\s+(?:const\s+fn|async\s+fn|unsafe\s+fn|fn|struct|enum|trait|"
    r"type|const|static|mod|use)\s+([A-Za-z_][A-Za-z0-9_]*)",
    re.M,
)


def module_path(path: Path) -> tuple[str, ...]:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] in ("mod", "lib"):
        parts.pop()
    return tuple(parts)


def code_of(text: str) -> str:
    """The text without comments and without a trailing `#[cfg(test)]` module."""
    cut = re.search(r"^#\[cfg\(test\)\]\s*\nmod tests", text, re.M)
    if cut:
        text = text[: cut.start()]
    text = re.sub(r"//[^\n]*", "", text)
    return re.sub(r"/\*.*?\*/", "", text, flags=re.S)


def use_trees(code: str) -> Iterator[tuple[list[str], int]]:
    """Each `crate::a::b::c` path, with `use crate::{x::y, z}` groups expanded."""
    for match in re.finditer(r"(?<![A-Za-z0-9_$])crate((?:::[A-Za-z0-9_]+)*)(::\{)?", code):
        prefix = [p for p in match.group(1).split("::") if p]
        line = code.count("\n", 0, match.start()) + 1
        if match.group(2):
            depth, i = 1, match.end()
            while depth and i < len(code):
                depth += {"{": 1, "}": -1}.get(code[i], 0)
                i += 1
            for path in expand(code[match.end() : i - 1]):
                yield prefix + path, line
        else:
            yield prefix, line


def expand(group: str) -> Iterator[list[str]]:
    """The paths of a use group's body `a::b, c::{d, e}, f as g`."""
    items, depth, start = [], 0, 0
    for i, ch in enumerate(group + ","):
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
        elif ch == "," and depth == 0:
            items.append(group[start:i].strip())
            start = i + 1
    for item in filter(None, items):
        item = re.sub(r"\s+as\s+\w+$", "", item)
        inner = re.match(r"^((?:[A-Za-z0-9_]+::)*)\{(.*)\}$", item, re.S)
        if inner:
            head = [p for p in inner.group(1).split("::") if p]
            for path in expand(inner.group(2)):
                yield head + path
        else:
            yield [p for p in item.split("::") if p and p != "self"]


def main() -> int:
    files = {module_path(p): p for p in sorted(ROOT.rglob("*.rs"))}
    # Items each module defines or re-exports: name -> the module a path through it
    # reaches (itself, or the re-exported item's module).
    reexports: dict[tuple[str, ...], dict[str, tuple[str, ...]]] = {}
    for module, path in files.items():
        code = code_of(path.read_text())
        names: dict[str, tuple[str, ...]] = {}
        for match in re.finditer(r"^\s*pub use ([^;]+);", code, re.M):
            body = match.group(1).strip()
            if (
                body.startswith("crate::")
                or body.startswith("self::")
                or not body.startswith(("trust", "files", "cbr_core"))
            ):
                base = list(module)
                body = body.removeprefix("self::")
                if body.startswith("crate::"):
                    base, body = [], body.removeprefix("crate::")
                for tail in expand(body):
                    target = resolve(files, tuple(base) + tuple(tail[:-1]))
                    if target is not None:
                        names[tail[-1]] = target
        reexports[module] = names

    def reach(path: list[str]) -> tuple[str, ...] | None:
        """The module a `crate::` path names or takes an item from."""
        module: tuple[str, ...] = ()
        for part in path:
            if module + (part,) in files:
                module = module + (part,)
                continue
            seen = reexports.get(module, {})
            if part == "*":
                return module
            through = seen.get(part, seen.get("*"))
            if through is not None:
                module = through
                continue
            return module
        return module

    edges: dict[tuple[str, ...], dict[tuple[str, ...], int]] = {m: {} for m in files}
    for module, names in reexports.items():
        for target in names.values():
            if target != module:
                edges[module].setdefault(target, 1)
    for module, path in files.items():
        code = code_of(path.read_text())
        # `super::` is the parent module, `self::` this one: written out from the crate.
        code = re.sub(
            r"(?<![A-Za-z0-9_$])super::", "crate::" + "".join(p + "::" for p in module[:-1]), code
        )
        code = re.sub(
            r"(?<![A-Za-z0-9_$:])self::", "crate::" + "".join(p + "::" for p in module), code
        )
        for tree, line in use_trees(code):
            target = reach(tree)
            if target is not None and target != module and target != ():
                edges[module].setdefault(target, line)

    problems = []
    rank = {folder: i for i, folder in enumerate(FOLDERS)}
    for module, targets in edges.items():
        if not module:
            continue  # lib.rs: the crate's facade re-exports from every folder
        own = rank.get(module[0]) if module else None
        for target, line in targets.items():
            theirs = rank.get(target[0]) if target else None
            where = f"{files[module]}:{line}"
            if own is None and theirs is not None and module[0] not in ROOT_CONSUMERS:
                problems.append(f"{where}: a shared module imports {'::'.join(target)}")
            elif own is not None and theirs is not None and theirs > own:
                problems.append(
                    f"{where}: {module[0]} imports {'::'.join(target)}, of a later folder"
                )
    for module, path in files.items():
        problems.extend(too_long(path))
    for cycle in cycles(edges):
        chain = " -> ".join("::".join(m) for m in cycle + [cycle[0]])
        problems.append(f"{files[cycle[0]]}: modules import each other: {chain}")
    if "--edges" in sys.argv:
        for module, targets in sorted(edges.items()):
            print("::".join(module), "->", ", ".join("::".join(t) for t in targets))
    for problem in problems:
        print(problem)
    if problems:
        return 1
    print(f"lab layers ok: {len(files)} modules, {sum(map(len, edges.values()))} imports")
    return 0


def too_long(path: Path) -> list[str]:
    """The file's length before its tests, and each function's, over the limits."""
    text = path.read_text()
    cut = re.search(r"^#\[cfg\(test\)\]\s*\nmod tests", text, re.M)
    lines = (text[: cut.start()] if cut else text).split("\n")
    found = []
    if len(lines) - 1 > MAX_FILE_LINES:
        found.append(f"{path}: {len(lines) - 1} lines before its tests (at most {MAX_FILE_LINES})")
    for i, line in enumerate(lines):
        signature = re.match(r"^\s*(?:pub(?:\([a-z]+\))?\s+)?(?:const\s+)?fn\s+(\w+)", line)
        if not signature:
            continue
        depth, opened, j = 0, False, i
        while j < len(lines):
            if not opened and lines[j].rstrip().endswith(";"):
                break
            for ch in lines[j]:
                depth += {"{": 1, "}": -1}.get(ch, 0)
                opened = opened or ch == "{"
            if opened and depth == 0:
                break
            j += 1
        if opened and j - i + 1 > MAX_FN_LINES:
            name = signature.group(1)
            found.append(f"{path}:{i + 1}: fn {name} is {j - i + 1} lines (at most {MAX_FN_LINES})")
    return found


def resolve(files: dict[Module, Path], module: Module) -> Module | None:
    while module and module not in files:
        module = module[:-1]
    return module if module in files else None


def cycles(edges: dict[Module, dict[Module, int]]) -> list[list[Module]]:
    """The strongly connected components of more than one module (Tarjan)."""
    index: dict[Module, int] = {}
    low: dict[Module, int] = {}
    stack: list[Module] = []
    on: set[Module] = set()
    found: list[list[Module]] = []

    def visit(v: Module) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in edges[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    sys.setrecursionlimit(10000)
    for v in list(edges):
        if v not in index:
            visit(v)
    return found


if __name__ == "__main__":
    sys.exit(main())
