"""The Rust core's modules depend downwards only (the order `rust/core/src/lib.rs` states):
every `crate::<module>` path in a file names its own top-level module or a lower layer; the
core crate has no pyo3 in its manifest (the binding crate is the only one that does); and in
either crate the modules of any one folder use each other without a cycle."""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import pytest

CORE = Path(__file__).resolve().parents[1] / "rust" / "core"

#: Lowest first; modules on one layer may not use each other either.
LAYERS = [
    ["error"],
    ["parallel", "progress", "geometry"],
    ["data", "evidence"],
    ["estimation"],
    ["assign"],
    ["fti", "static_los", "formation", "topology", "radar_esm"],
]
LAYER = {name: k for k, names in enumerate(LAYERS) for name in names}


def _top_module(path: Path) -> str:
    return path.relative_to(CORE / "src").parts[0].removesuffix(".rs")


@pytest.mark.skipif(not CORE.exists(), reason="needs the source tree")
def test_core_modules_depend_downwards() -> None:
    wrong = []
    files = [p for p in sorted((CORE / "src").rglob("*.rs")) if p.name != "lib.rs"]
    assert len(files) > 40, "the core's sources were not found"
    for path in files:
        own = _top_module(path)
        assert own in LAYER, f"{own} has no layer: add it to LAYERS"
        for target in set(re.findall(r"\bcrate::([a-z_]+)", path.read_text())):
            if target != own and LAYER[target] >= LAYER[own]:
                wrong.append(f"{path.relative_to(CORE)} uses crate::{target}")
    assert not wrong, "dependencies pointing sideways or up:\n" + "\n".join(wrong)


@pytest.mark.skipif(not CORE.exists(), reason="needs the source tree")
def test_core_crate_has_no_python() -> None:
    manifest = tomllib.loads((CORE / "Cargo.toml").read_text())
    deps = {**manifest.get("dependencies", {}), **manifest.get("dev-dependencies", {})}
    assert "pyo3" not in deps and "numpy" not in deps
    assert not [p for p in (CORE / "src").rglob("*.rs") if "pyo3" in p.read_text()]


# Cycles inside one folder ------------------------------------------------------------------
#
# Within a folder (a module and its submodules) the files are layered too: shared types at the
# bottom, stages above them, the driver on top. The check below builds, for every module with
# submodules, the graph "child a names an item of child b" from every path a file spells
# (`use` trees and `crate::`/`super::`/`self::` paths in code, resolved through the names a
# `mod.rs` re-exports) and fails on any cycle. Test code (`#[cfg(test)]` items and modules
# declared under `#[cfg(test)]`) sits above what it tests and is left out: a stage's unit
# test may drive the stages around it.

RUST_SOURCES = [CORE / "src", CORE.parent / "src"]

_IDENT = r"[A-Za-z_][A-Za-z0-9_]*"
_CHAR = re.compile(r"'(?:\\(?:x[0-9a-fA-F]{2}|u\{[0-9a-fA-F]+\}|.)|[^\\'\n])'")
_RAW_STRING = re.compile(r'b?r(#*)"')
_CFG_TEST = re.compile(r"#\s*\[\s*cfg\s*\(\s*test\s*\)\s*\]")
_MOD_DECL = re.compile(rf"^\s*(?:pub(?:\s*\([^)]*\))?\s+)?mod\s+({_IDENT})\s*;")
_INLINE_MOD = re.compile(rf"(?<![\w:])mod\s+({_IDENT})\s*\{{")
_USE = re.compile(r"(?<![\w:])use\s+([^;]+);")
_CODE_PATH = re.compile(rf"(?<![\w:])(?:crate|super|self)(?:\s*::\s*{_IDENT})+")


def _strip_rust(code: str) -> str:
    """`code` without comments and string or char literals (each literal left as `""`)."""
    out, i, n = [], 0, len(code)
    while i < n:
        if code.startswith("//", i):
            end = code.find("\n", i)
            i = n if end < 0 else end
        elif code.startswith("/*", i):
            depth, i = 1, i + 2
            while i < n and depth:
                if code.startswith(("/*", "*/"), i):
                    depth += 1 if code[i + 1] == "*" else -1
                    i += 2
                else:
                    i += 1
            out.append(" ")
        elif (raw := _RAW_STRING.match(code, i)) and not (i and re.match(r"\w", code[i - 1])):
            close = '"' + raw.group(1)
            end = code.find(close, raw.end())
            i = n if end < 0 else end + len(close)
            out.append('""')
        elif code[i] == '"':
            i += 1
            while i < n and code[i] != '"':
                i += 2 if code[i] == "\\" else 1
            i += 1
            out.append('""')
        elif code[i] == "'" and (char := _CHAR.match(code, i)):
            i = char.end()
            out.append("''")
        else:
            out.append(code[i])
            i += 1
    return "".join(out)


def _item_end(code: str, i: int) -> int:
    """The end of the item starting at `i`: its `;` or its closing brace, at depth 0."""
    depth = 0
    while i < len(code):
        c = code[i]
        if c in "([":
            depth += 1
        elif c in ")]":
            depth -= 1
        elif c == ";" and depth == 0:
            return i + 1
        elif c == "{" and depth == 0:
            return _block_end(code, i)
        i += 1
    return i


def _block_end(code: str, i: int) -> int:
    """The index past the brace that closes the `{` at `i`."""
    depth = 0
    for k in range(i, len(code)):
        depth += {"{": 1, "}": -1}.get(code[k], 0)
        if depth == 0:
            return k + 1
    return len(code)


def _without_tests(code: str) -> tuple[str, set[str]]:
    """`code` without its `#[cfg(test)]` items, and the modules those declare (`mod x;`)."""
    test_modules = set()
    while found := _CFG_TEST.search(code):
        end = _item_end(code, found.end())
        if declared := _MOD_DECL.match(re.sub(r"#\s*\[[^\]]*\]", "", code[found.end() : end])):
            test_modules.add(declared.group(1))
        code = code[: found.start()] + " " + code[end:]
    return code, test_modules


def _use_leaves(tree: str) -> list[tuple[list[str], str | None]]:
    """Each leaf of a `use` tree: its path and the name it binds (`None` for a glob)."""
    tokens = re.findall(rf"::|[{{}},*]|{_IDENT}", tree)
    leaves: list[tuple[list[str], str | None]] = []

    def parse(pos: int, prefix: list[str]) -> int:
        path = list(prefix)
        while pos < len(tokens):
            tok = tokens[pos]
            if tok == "::":
                pos += 1
            elif tok == "{":
                pos += 1
                while pos < len(tokens) and tokens[pos] != "}":
                    pos = parse(pos, path)
                    if pos < len(tokens) and tokens[pos] == ",":
                        pos += 1
                return pos + 1
            elif tok == "*":
                leaves.append((path, None))
                return pos + 1
            elif tok in (",", "}"):
                return pos
            else:
                pos += 1
                if pos < len(tokens) and tokens[pos] == "::":
                    path.append(tok)
                    continue
                name = tok
                if pos + 1 < len(tokens) and tokens[pos] == "as":
                    name, pos = tokens[pos + 1], pos + 2
                if tok == "self":  # `x::{self}` binds x
                    leaves.append((path, path[-1] if name == "self" and path else name))
                else:
                    leaves.append(([*path, tok], name))
                return pos
        return pos

    parse(0, [])
    return leaves


def _file_module(src: Path, path: Path) -> tuple[str, ...]:
    parts = path.relative_to(src).with_suffix("").parts
    return parts[:-1] if parts[-1] in ("mod", "lib", "main") else parts


class _Crate:
    """The modules of one crate, the names each binds with `use`, and the paths each spells."""

    def __init__(self, src: Path) -> None:
        self.src = src
        self.modules: set[tuple[str, ...]] = set()
        self.tests: set[tuple[str, ...]] = set()
        #: (module, file, raw path) of every path spelled outside `use`, and of every use leaf.
        self.paths: list[tuple[tuple[str, ...], str, list[str]]] = []
        self.raw_uses: dict[tuple[str, ...], list[tuple[list[str], str | None]]] = {}
        files = sorted(src.rglob("*.rs"))
        for path in files:
            own = _file_module(src, path)
            code, test_modules = _without_tests(_strip_rust(path.read_text()))
            self.tests |= {(*own, name) for name in test_modules}
            self.modules.add(own)
            spans = [
                (found.start(), _block_end(code, found.end() - 1), found.group(1))
                for found in _INLINE_MOD.finditer(code)
            ]

            def module_at(at: int, own: tuple[str, ...] = own, spans: list = spans) -> tuple:
                """The module of the code at offset `at`: the file's, or an inline one."""
                inside = [name for start, end, name in spans if start <= at < end]
                return (*own, *inside)

            self.modules |= {(*module_at(start), name) for start, _, name in spans}

            rel = str(path.relative_to(src))
            for found in _USE.finditer(code):
                module = module_at(found.start())
                for leaf in _use_leaves(found.group(1)):
                    self.raw_uses.setdefault(module, []).append(leaf)
                    self.paths.append((module, rel, leaf[0]))
            uses_blanked = _USE.sub(lambda use: " " * len(use.group(0)), code)
            for found in _CODE_PATH.finditer(uses_blanked):
                segments = re.findall(_IDENT, found.group(0))
                self.paths.append((module_at(found.start()), rel, segments))
        self.modules = {m for m in self.modules if not self._in_tests(m)}
        self.paths = [p for p in self.paths if not self._in_tests(p[0])]
        self.aliases: dict[tuple[str, ...], dict[str, list[str]]] = {}
        self.globs: dict[tuple[str, ...], list[list[str]]] = {}
        for module, leaves in self.raw_uses.items():
            for raw, name in leaves:
                absolute = self.absolute(module, raw, local=False)
                if absolute is None:
                    continue
                if name is None:
                    self.globs.setdefault(module, []).append(absolute)
                elif name != "_":
                    self.aliases.setdefault(module, {})[name] = absolute

    def _in_tests(self, module: tuple[str, ...]) -> bool:
        return any(module[: len(t)] == t for t in self.tests)

    def absolute(self, module: tuple[str, ...], raw: list[str], local: bool = True) -> list | None:
        """`raw` spelled in `module` as a path from the crate root; `None` outside the crate."""
        if not raw:
            return None
        first = raw[0]
        if first == "crate":
            return raw[1:]
        if first in ("super", "self"):
            base = list(module)
            rest = list(raw)
            while rest and rest[0] in ("super", "self"):
                if rest.pop(0) == "super":
                    base = base[:-1]
            return base + rest
        if (*module, first) in self.modules:
            return [*module, *raw]
        if local and first in self.aliases.get(module, {}):
            return self.aliases[module][first] + raw[1:]
        return None  # another crate, or a name this check does not follow

    def defining_module(self, path: list[str], seen: frozenset = frozenset()) -> tuple:
        """The module that defines what `path` names, following `use` re-exports."""
        current: tuple[str, ...] = ()
        for k, segment in enumerate(path):
            if (*current, segment) in self.modules:
                current = (*current, segment)
                continue
            key = (current, segment)
            target = self.aliases.get(current, {}).get(segment)
            if target is not None and key not in seen:
                return self.defining_module(target + path[k + 1 :], seen | {key})
            for glob in self.globs.get(current, []):
                inner = self.defining_module([*glob, *path[k:]], seen | {key})
                if len(inner) > len(glob) or segment in self.aliases.get(tuple(glob), {}):
                    return inner
            return current
        return current

    def folder_edges(self) -> dict[tuple, dict[tuple[str, str], set[str]]]:
        """Per module: (child, child) → the files and paths that make the first use the second."""
        edges: dict[tuple, dict[tuple[str, str], set[str]]] = {}
        for module, rel, raw in self.paths:
            absolute = self.absolute(module, raw)
            if absolute is None:
                continue
            target = self.defining_module(absolute)
            common = 0
            while common < min(len(module), len(target)) and module[common] == target[common]:
                common += 1
            if common < len(module) and common < len(target):
                folder = module[:common]
                pair = (module[common], target[common])
                edges.setdefault(folder, {}).setdefault(pair, set()).add(f"{rel}: {'::'.join(raw)}")
        return edges


def _strongly_connected(nodes: set[str], edges: set[tuple[str, str]]) -> list[list[str]]:
    """Tarjan's strongly connected components of more than one node, each sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []
    successors = {n: sorted(b for a, b in edges if a == n) for n in nodes}

    def visit(node: str) -> None:
        index[node] = low[node] = len(index)
        stack.append(node)
        on_stack.add(node)
        for succ in successors[node]:
            if succ not in index:
                visit(succ)
                low[node] = min(low[node], low[succ])
            elif succ in on_stack:
                low[node] = min(low[node], index[succ])
        if low[node] == index[node]:
            component = []
            while True:
                top = stack.pop()
                on_stack.discard(top)
                component.append(top)
                if top == node:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for node in sorted(nodes):
        if node not in index:
            visit(node)
    return found


def folder_cycles(src: Path) -> list[str]:
    """Every cycle among the children of one module of the crate at `src`, described."""
    crate = _Crate(src)
    cycles = []
    for folder, pairs in sorted(crate.folder_edges().items()):
        nodes = {n for pair in pairs for n in pair}
        for component in _strongly_connected(nodes, set(pairs)):
            where = "::".join(("crate", *folder))
            lines = [f"{where}: {' ↔ '.join(component)}"]
            for (a, b), uses in sorted(pairs.items()):
                if a in component and b in component:
                    lines.append(f"  {a} → {b}: " + "; ".join(sorted(uses)[:4]))
            cycles.append("\n".join(lines))
    return cycles


@pytest.mark.skipif(not CORE.exists(), reason="needs the source tree")
@pytest.mark.parametrize("src", RUST_SOURCES, ids=["core", "binding"])
def test_no_cycles_inside_a_folder(src: Path) -> None:
    crate = _Crate(src)
    assert len(crate.modules) > 10 and sum(len(p) for p in crate.folder_edges().values()) > 10
    cycles = folder_cycles(src)
    assert not cycles, "modules of one folder that use each other:\n" + "\n".join(cycles)


def _write_tree(root: Path, files: dict[str, str]) -> Path:
    for name, text in files.items():
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text(text)
    return root


_CLEAN_TREE = {
    "lib.rs": "pub mod stage;\npub mod shared;\n",
    "shared.rs": "pub struct Row;\n",
    "stage/mod.rs": (
        "mod driver;\nmod parts;\nmod types;\n#[cfg(test)]\nmod tests;\n"
        "pub use types::{Candidate, Pair as RayPair};\npub use driver::run;\n"
    ),
    "stage/types.rs": (
        "pub struct Candidate;\npub struct Pair;\n"
        "#[cfg(test)]\n#[allow(unused)]\nmod tests {\n    use crate::stage::driver::run;\n}\n"
    ),
    "stage/parts/mod.rs": "mod fit;\nmod gate;\npub(crate) use fit::fit;\n",
    "stage/parts/fit.rs": (
        "use super::super::{types::Candidate, RayPair};\nuse crate::shared::Row;\n"
        "pub fn fit(_: &RayPair, _: Row) -> Candidate { Candidate }\n"
    ),
    "stage/parts/gate.rs": (
        "// use super::super::driver::run;  (a comment names no module)\n"
        'const NOTE: &str = "crate::stage::driver::run";\n'
        "pub fn keep() -> bool { self::inner::yes() }\nmod inner { pub fn yes() -> bool { true } }\n"
        "pub fn fit_one() { super::fit::fit(todo!(), todo!()); }\n"
    ),
    "stage/driver.rs": (
        "use super::parts;\nuse self::helper::help;\nmod helper { pub fn help() {} }\n"
        "pub fn run() { help(); let _ = crate::stage::parts::fit; }\n"
    ),
    "stage/tests.rs": "use super::driver::run;\nuse super::*;\n",
}


def test_the_cycle_check_passes_a_clean_tree(tmp_path: Path) -> None:
    src = _write_tree(tmp_path, _CLEAN_TREE)
    crate = _Crate(src)
    edges = crate.folder_edges()
    assert set(edges[("stage",)]) == {("parts", "types"), ("driver", "parts")}
    assert set(edges[("stage", "parts")]) == {("gate", "fit")}
    assert set(edges[()]) == {("stage", "shared")}
    assert ("stage", "tests") not in crate.modules
    assert folder_cycles(src) == []


@pytest.mark.parametrize(
    ("path", "text", "cycle"),
    [
        # through a name mod.rs re-exports from another file
        ("stage/types.rs", "use super::run;\npub struct Candidate;\npub struct Pair;\n", "driver"),
        # a grouped use tree, a path in code, `self::`-relative and `crate::` paths
        ("stage/types.rs", "use super::{driver::run as go};\npub struct Candidate;\n", "driver"),
        ("stage/types.rs", "pub struct Candidate;\nfn f() { crate::stage::run(); }\n", "driver"),
        ("stage/parts/fit.rs", "use crate::stage::parts::gate::keep;\n", "gate"),
        ("stage/parts/gate.rs", "pub fn keep() { self::super::fit::fit(); }\n", "NONE"),
        ("shared.rs", "use crate::stage::Candidate;\npub struct Row;\n", "stage"),
    ],
)
def test_the_cycle_check_finds_a_cycle(tmp_path: Path, path: str, text: str, cycle: str) -> None:
    files = dict(_CLEAN_TREE)
    files[path] = text
    cycles = folder_cycles(_write_tree(tmp_path, files))
    if cycle == "NONE":
        assert cycles == []
    else:
        assert len(cycles) == 1 and cycle in cycles[0], cycles
