"""Documentation that runs: the README's Python example and the docstring examples."""

from __future__ import annotations

import doctest
import importlib
import pkgutil
import re
from pathlib import Path

import passive_assoc
import pytest

ROOT = Path(__file__).resolve().parents[1]


def _public_modules() -> list[str]:
    """Every module of the package whose dotted name has no private (``_``) part."""
    names = [passive_assoc.__name__]
    for info in pkgutil.walk_packages(passive_assoc.__path__, prefix=f"{passive_assoc.__name__}."):
        if not any(part.startswith("_") for part in info.name.split(".")):
            names.append(info.name)
    return sorted(names)


def _modules_with_examples() -> list[str]:
    finder = doctest.DocTestFinder()
    return [
        name for name in _public_modules() if any(test.examples for test in finder.find(importlib.import_module(name)))
    ]


DOCTEST_MODULES = _modules_with_examples()


def test_readme_example_runs() -> None:
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, re.S)
    assert blocks, "README has no Python example"
    for code in blocks:
        exec(compile(code, "README.md", "exec"), {})


def test_docstring_examples_are_collected() -> None:
    """The modules known to carry examples are found, so a broken finder cannot pass silently."""
    assert {"passive_assoc.estimation.fitting", "passive_assoc.assignment.sd"} <= set(DOCTEST_MODULES)


@pytest.mark.parametrize("module", DOCTEST_MODULES)
def test_docstring_examples(module: str) -> None:
    failed, attempted = doctest.testmod(importlib.import_module(module), optionflags=doctest.ELLIPSIS)
    assert attempted > 0 and failed == 0
