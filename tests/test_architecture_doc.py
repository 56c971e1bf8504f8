"""docs/architecture.md's layout says what is: every path it names exists, and every source file
of the Rust crates and the Python package is named there, exactly once.

The layout is the first ```text block after the ``## Layout`` heading. Each non-blank line is a
path, then two or more spaces and what the path holds (a folder line may have no text). A path
ending in ``/`` is a folder; the lines indented under it are inside it, their paths relative to
it; an unindented path is relative to the repository. A path may hold one ``{a,b,c}`` group,
which names each expansion (``tests/{mod,sim}.rs`` names ``tests/mod.rs`` and ``tests/sim.rs``).
"""

from __future__ import annotations

import re
from collections import Counter
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOC = ROOT / "docs" / "architecture.md"

_BLOCK = re.compile(r"^## Layout\n.*?^```text\n(.*?)^```", re.S | re.M)
_LINE = re.compile(r"( *)(\S+)(?: {2,}\S.*)?")
_BRACES = re.compile(r"\{([^{}]*)\}")


def layout_block(markdown: str) -> str:
    """The text of the layout's ```text block."""
    match = _BLOCK.search(markdown)
    if match is None:
        raise ValueError("no ```text block after '## Layout'")
    return match.group(1)


def _expand(path: str) -> list[str]:
    match = _BRACES.search(path)
    if match is None:
        return [path]
    if _BRACES.search(path, match.end()) or "{" in path[match.end() :]:
        raise ValueError(f"{path!r}: more than one {{…}} group")
    return [path[: match.start()] + name.strip() + path[match.end() :] for name in match.group(1).split(",")]


def named_paths(block: str) -> list[str]:
    """Every path the layout block names, relative to the repository, in order: folders end in
    ``/``. Raises ``ValueError`` on a line that breaks the convention."""
    paths: list[str] = []
    folders: list[tuple[int, str]] = []  # (indent, path) of the open folders, innermost last
    previous: tuple[int, str] | None = None
    for number, line in enumerate(block.splitlines(), 1):
        if not line.strip():
            continue
        match = _LINE.fullmatch(line.rstrip())
        if match is None:
            raise ValueError(f"layout line {number}: not 'path  text': {line!r}")
        indent, token = len(match.group(1)), match.group(2)
        if previous is not None and indent > previous[0] and not previous[1].endswith("/"):
            raise ValueError(f"layout line {number}: indented under a file: {line!r}")
        while folders and folders[-1][0] >= indent:
            folders.pop()
        if indent and not folders:
            raise ValueError(f"layout line {number}: indented under no folder: {line!r}")
        if token.startswith("/") or ".." in token.split("/"):
            raise ValueError(f"layout line {number}: not a relative path: {token!r}")
        parent = folders[-1][1] if folders else ""
        expanded = [parent + name for name in _expand(token)]
        if token.endswith("/"):
            if len(expanded) != 1:
                raise ValueError(f"layout line {number}: a folder line names one folder: {token!r}")
            folders.append((indent, expanded[0]))
        paths += expanded
        previous = (indent, token)
    return paths


def source_files(root: Path) -> set[str]:
    """The source files the layout must name: ``*.rs`` under ``rust/`` and ``*.py`` / ``*.pyi``
    under ``python/passive_assoc/``, without build output (``target/``, ``__pycache__/``)."""
    found = [*(root / "rust").rglob("*.rs")]
    for pattern in ("*.py", "*.pyi"):
        found += (root / "python" / "passive_assoc").rglob(pattern)
    skip = {"target", "__pycache__"}
    return {path.relative_to(root).as_posix() for path in found if not skip & set(path.relative_to(root).parts)}


def layout_problems(root: Path, markdown: str) -> dict[str, list[str]]:
    """What is wrong with the layout of ``markdown`` against the tree at ``root``: paths named
    that do not exist (or are a file where a folder is named, or the reverse), paths named more
    than once, and source files not named."""
    paths = named_paths(layout_block(markdown))
    missing = [
        path for path in paths if not ((root / path).is_dir() if path.endswith("/") else (root / path).is_file())
    ]
    repeated = sorted(path for path, count in Counter(paths).items() if count > 1)
    unnamed = sorted(source_files(root) - set(paths))
    return {"missing": missing, "repeated": repeated, "unnamed": unnamed}


@pytest.mark.skipif(not (ROOT / "rust").exists(), reason="needs the source tree")
def test_layout_matches_the_tree() -> None:
    markdown = DOC.read_text(encoding="utf-8")
    assert len(source_files(ROOT)) > 200, "the source files were not found"
    assert len(named_paths(layout_block(markdown))) > 200, "the layout block was not read"
    problems = layout_problems(ROOT, markdown)
    assert problems == {"missing": [], "repeated": [], "unnamed": []}, problems


# The checker itself, on a synthetic tree, so that it cannot pass by reading nothing --------

SYNTHETIC = """# Architecture

## Layout

```text
Cargo.toml              the workspace
rust/core/              the core
  src/
    lib.rs              the modules
    gone.rs             a file that was never there
    tests/{mod,sim}.rs  the tests
python/passive_assoc/   the package
  __init__.py           the names
```

```text
rust/core/src/extra.rs  a later block is not the layout
```
"""


def _tree(root: Path, files: list[str]) -> None:
    for name in files:
        (root / name).parent.mkdir(parents=True, exist_ok=True)
        (root / name).write_text("")


def test_the_parser_reads_folders_indents_and_groups() -> None:
    assert named_paths(layout_block(SYNTHETIC)) == [
        "Cargo.toml",
        "rust/core/",
        "rust/core/src/",
        "rust/core/src/lib.rs",
        "rust/core/src/gone.rs",
        "rust/core/src/tests/mod.rs",
        "rust/core/src/tests/sim.rs",
        "python/passive_assoc/",
        "python/passive_assoc/__init__.py",
    ]


def test_the_checker_catches_a_missing_and_an_unnamed_file(tmp_path: Path) -> None:
    _tree(
        tmp_path,
        [
            "Cargo.toml",
            "rust/core/src/lib.rs",
            "rust/core/src/tests/mod.rs",
            "rust/core/src/tests/sim.rs",
            "rust/core/src/extra.rs",  # on disk, not named
            "python/passive_assoc/__init__.py",
            "python/passive_assoc/__pycache__/cached.py",  # build output: need not be named
        ],
    )
    assert layout_problems(tmp_path, SYNTHETIC) == {
        "missing": ["rust/core/src/gone.rs"],
        "repeated": [],
        "unnamed": ["rust/core/src/extra.rs"],
    }


def test_the_checker_catches_a_repeat_and_a_folder_named_as_a_file(tmp_path: Path) -> None:
    _tree(tmp_path, ["rust/a.rs"])
    text = "## Layout\n\n```text\nrust/a.rs  once\nrust/     the folder\n  a.rs    twice\nrust      no slash\n```\n"
    assert layout_problems(tmp_path, text) == {"missing": ["rust"], "repeated": ["rust/a.rs"], "unnamed": []}


@pytest.mark.parametrize(
    "block",
    [
        "a.rs  a file\n  b.rs  under a file\n",  # only a folder has lines under it
        "  b.rs  under nothing\n",
        "a.rs one space\n",  # the text needs two spaces before it
        "x/{a,b}/  a group of folders\n",
        "../a.rs  outside the repository\n",
    ],
)
def test_the_parser_refuses_a_line_off_the_convention(block: str) -> None:
    with pytest.raises(ValueError):
        named_paths(block)
