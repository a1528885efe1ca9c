#!/usr/bin/env python3
"""Fails when a crate's modules import each other in a cycle (a module importing its importer).

For every crate below the given folders (each `Cargo.toml` beside a `src/`), every top-level
module of `src/` (a file `src/m.rs` or a folder `src/m/`) gets an edge to each other top-level
module it names as `crate::other` (in `use` lines and paths alike, macros included), leaving
out its test modules (`tests.rs`, `tests/`, `test_support`, `testutil`). The same is done one level down,
among the sub-modules of each folder module (`super::x` and `crate::m::x`). Any strongly
connected set of more than one module is printed and the exit status is 1. The generated J2735
modules (`codec/src/generated/`) are left out: they import each other as the standard's ASN.1
modules do.

Usage: tests/tools/module_cycles.py [--graph] [FOLDER...]   (default: the repository)
"""
import pathlib
import re
import sys

TEST_PARTS = {"tests", "tests.rs", "test_support.rs", "testutil.rs", "testdata.rs"}


def rust_files(path):
    if path.is_file():
        return [path]
    return [p for p in sorted(path.rglob("*.rs")) if not TEST_PARTS & set(p.relative_to(path).parts)]


def strip_tests(text):
    """The text without `#[cfg(test)] mod x { ... }` blocks and comments."""
    text = re.sub(r"//[^\n]*", "", text)
    out, i = [], 0
    for m in re.finditer(r"#\[cfg\(test\)\]\s*(pub\s+)?mod\s+\w+\s*\{", text):
        if m.start() < i:
            continue
        out.append(text[i:m.start()])
        depth, j = 1, m.end()
        while j < len(text) and depth:
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            j += 1
        i = j
    out.append(text[i:])
    return "".join(out)


def modules(src):
    """Top-level modules of a source folder: name -> path (file or folder)."""
    found = {}
    for p in src.iterdir():
        if p.name in ("lib.rs", "main.rs", "mod.rs") or p.name in TEST_PARTS:
            continue
        if p.suffix == ".rs":
            found.setdefault(p.stem, p)
        elif p.is_dir():
            found[p.name] = p
    # A module `m.rs` with a folder `m/`: both are module m.
    return found


def edges(mods, prefix_patterns):
    graph = {m: set() for m in mods}
    for m, path in mods.items():
        files = rust_files(path)
        sibling = path.parent / f"{m}.rs"
        if path.is_dir() and sibling.exists():
            files.append(sibling)
        for f in files:
            text = strip_tests(f.read_text())
            for pat in prefix_patterns:
                for other in re.findall(pat, text):
                    if other != m and other in mods:
                        graph[m].add(other)
            # `use crate::{a, b::c}` groups.
            for group in re.findall(r"use\s+crate::\{([^}]*)\}", text):
                for other in re.findall(r"(?:^|,)\s*(\w+)", group):
                    if other != m and other in mods:
                        graph[m].add(other)
    return graph


def cycles(graph):
    """Strongly connected sets of more than one module (Tarjan)."""
    index, low, stack, on, out, n = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = n[0]
        n[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def main(argv):
    show = "--graph" in argv
    roots = [pathlib.Path(a) for a in argv if a != "--graph"] or [pathlib.Path(__file__).resolve().parents[2]]
    bad = 0
    checked = 0
    for root in roots:
        for toml in sorted(root.rglob("Cargo.toml")):
            src = toml.parent / "src"
            if not src.is_dir() or "target" in toml.parts or "generated" in toml.parts:
                continue
            crate = toml.parent
            levels = [(str(crate.relative_to(root)) or ".", modules(src), [r"crate::(\w+)"])]
            for name, path in modules(src).items():
                # The generated J2735 modules import each other as the ASN.1 modules do.
                if path.is_dir() and name != "generated":
                    sub = modules(path)
                    pats = [r"super::(\w+)", rf"crate::{name}::(\w+)"]
                    levels.append((f"{crate.relative_to(root)}::{name}", sub, pats))
            for where, mods, pats in levels:
                graph = edges(mods, pats)
                checked += 1
                if show:
                    for m in sorted(graph):
                        print(f"{where}: {m} -> {', '.join(sorted(graph[m])) or '-'}")
                for c in cycles(graph):
                    bad += 1
                    print(f"cycle in {where}: {' <-> '.join(c)}")
    print(f"{checked} module levels checked, {bad} cycle(s)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
