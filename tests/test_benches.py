"""The benches' own contract: every ``benches/*.py`` parses and opens with a docstring whose
first line says what it measures (no issue numbers), and the project's mypy run checks them."""

from __future__ import annotations

import ast
import re
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BENCHES = sorted((ROOT / "benches").glob("*.py"))
#: The word "issue" followed by a number (with or without "#"): the tracker's numbers are
#: history, which belongs in CHANGELOG.md.
ISSUE = re.compile(r"\bissue\s*#?\s*\d+", re.IGNORECASE)


def test_benches_are_found() -> None:
    """The glob finds the benches, so an empty directory cannot pass the tests below silently."""
    assert len(BENCHES) >= 20


@pytest.mark.parametrize("path", BENCHES, ids=lambda path: path.name)
def test_bench_docstring_says_what_it_measures(path: Path) -> None:
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    docstring = ast.get_docstring(tree)
    assert docstring, f"{path.name} has no module docstring"
    first = docstring.splitlines()[0].strip()
    assert first, f"{path.name}: the docstring's first line is empty"
    assert not ISSUE.search(first), f"{path.name}: the first line cites an issue: {first!r}"
    assert not ISSUE.search(docstring), f"{path.name}: the docstring cites an issue"


def test_mypy_checks_the_benches() -> None:
    config = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    files = config["tool"]["mypy"]["files"]
    assert "benches" in [name.rstrip("/") for name in files]
