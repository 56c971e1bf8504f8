"""The user guide and the docs' landing page run: every ```python block of docs/guide.md and
docs/index.md is executed on its own, in a fresh namespace, so the pages cannot go stale."""

from __future__ import annotations

import re
import warnings
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = ("docs/guide.md", "docs/index.md")

#: A block using one of these needs the optional extra's module; it is skipped without it.
EXTRAS = {
    "interop.stonesoup": "stonesoup",
    "parquet": "pyarrow",
    "to_pandas": "pandas",
    "from_pandas": "pandas",
}


def _blocks() -> list[tuple[str, str]]:
    """``(page:line, code)`` of every ```python block, in page order."""
    found = []
    for page in PAGES:
        text = (ROOT / page).read_text()
        for match in re.finditer(r"^```python\n(.*?)^```", text, re.S | re.M):
            line = text.count("\n", 0, match.start()) + 2  # the block's first code line
            found.append((f"{page}:{line}", match.group(1)))
    return found


BLOCKS = _blocks()


def test_the_guide_has_examples() -> None:
    """A change to the block syntax cannot silently leave nothing to run."""
    assert sum(where.startswith("docs/guide.md") for where, _ in BLOCKS) >= 5


@pytest.mark.parametrize(("where", "code"), BLOCKS, ids=[where for where, _ in BLOCKS])
def test_example_runs(where: str, code: str, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    for marker, module in EXTRAS.items():
        if marker in code:
            pytest.importorskip(module)
    monkeypatch.chdir(tmp_path)  # a block that writes relative paths writes here
    with warnings.catch_warnings():
        # The library's warnings (angles in degrees, ignored columns, no candidate) in an
        # example are a mistake in the example.
        warnings.simplefilter("error", UserWarning)
        exec(compile(code, where, "exec"), {"__name__": "__guide__"})
