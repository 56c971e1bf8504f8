"""The code and its documentation say what is, not how it came to be: no file under rust/,
python/, tests/, benches/ or docs/ cites a numbered issue, a numbered work period or a
development tool. History, with its measurements, belongs in CHANGELOG.md (at the top of the
repository, outside the folders checked)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FOLDERS = ["rust", "python", "tests", "benches", "docs"]
#: Build output and caches, not sources.
SKIP = {"__pycache__", "target", "site", ".pytest_cache", ".mypy_cache", ".ruff_cache", ".hypothesis"}

# Spelled in pieces so that this file, which is checked too, does not match itself.
_PERIOD = "sess" + "ion"
_ISSUE = "iss" + "ue"
_TOOLS = ["farm" + "-bench", "farm" + "-studio"]
#: A numbered work period, a development tool's name, or an issue number (the word, an
#: optional space and "#", then digits).
HISTORY = re.compile(rf"(?i)\b{_PERIOD}s? \d+|{'|'.join(_TOOLS)}|\b{_ISSUE} ?#?\d+")


def checked_files(root: Path) -> list[Path]:
    """Every text file under the checked folders of ``root`` (binary files, those holding a
    NUL byte, and build output are left out)."""
    files = []
    for folder in FOLDERS:
        for path in sorted((root / folder).rglob("*")):
            if not path.is_file() or SKIP & set(path.relative_to(root).parts):
                continue
            if b"\0" not in path.read_bytes():
                files.append(path)
    return files


def history_lines(root: Path) -> list[str]:
    """``path:line: text`` of every line under ``root``'s checked folders that cites history."""
    found = []
    for path in checked_files(root):
        text = path.read_bytes().decode("utf-8", errors="replace")
        for number, line in enumerate(text.splitlines(), 1):
            if HISTORY.search(line):
                found.append(f"{path.relative_to(root).as_posix()}:{number}: {line.strip()}")
    return found


@pytest.mark.skipif(not (ROOT / "rust").exists(), reason="needs the source tree")
def test_no_file_cites_history() -> None:
    assert len(checked_files(ROOT)) > 300, "the files to check were not found"
    found = history_lines(ROOT)
    assert not found, "history belongs in CHANGELOG.md:\n" + "\n".join(found)


@pytest.mark.parametrize(
    "text",
    [
        f"measured in {_PERIOD.title()} 18, with the spread",
        f"until {_PERIOD}s 16 and 17",
        f"the {_ISSUE} 16 scene",
        f"fixed by {_ISSUE.title()} #13",
        f"see {_ISSUE}#7",
        f"run by {_TOOLS[0]}",
        f"the {_TOOLS[1].upper()} layout",
    ],
)
def test_the_pattern_finds_history(text: str) -> None:
    assert HISTORY.search(text)


@pytest.mark.parametrize(
    "text",
    [
        f'@pytest.fixture(scope="{_PERIOD}")',
        f"a {_PERIOD}-scoped fixture",
        f"two {_ISSUE}s remain",
        f"t{_ISSUE} 5",
        "the farm bench",
    ],
)
def test_the_pattern_leaves_ordinary_words(text: str) -> None:
    assert not HISTORY.search(text)


def test_a_cited_issue_is_found_in_a_tree(tmp_path: Path) -> None:
    """The walk reads every checked folder and skips build output and binary files."""
    cited = f"{_ISSUE} 16"
    for name, text in [
        ("rust/core/src/lib.rs", "//! the core\n"),
        ("docs/methods.md", f"# Methods\n\nas in {cited} §3\n"),
        ("python/pkg/__pycache__/mod.py", f"# {cited}\n"),
        ("docs/figure.png", f"\0{cited}"),
        ("README.md", f"{cited}, outside the checked folders\n"),
    ]:
        (tmp_path / name).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / name).write_text(text)
    assert history_lines(tmp_path) == [f"docs/methods.md:3: as in {cited} §3"]
