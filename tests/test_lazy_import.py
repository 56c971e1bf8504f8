"""``import passive_assoc`` is cheap: the namespace imports its subpackages on first use, so
the import itself loads none of the heavy dependencies (checked in a fresh interpreter, by
module, not by a timing), and every re-exported name still resolves to what it names."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import passive_assoc as pa
import pytest

#: Modules a bare ``import passive_assoc`` must not load (each costs 0.03-0.9 s).
HEAVY = ("scipy.stats", "pywt", "matplotlib", "pandas", "dask")


def test_import_loads_no_heavy_dependency() -> None:
    code = f"import sys, passive_assoc; print(sorted(m for m in {HEAVY!r} if m in sys.modules))"
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True)
    assert done.stdout.strip() == "[]", done.stdout


def test_the_lazy_table_names_what_the_imports_import() -> None:
    """``_EXPORTS`` (what runs) and the ``TYPE_CHECKING`` imports (what type checkers read)
    list the same names from the same subpackages."""
    tree = ast.parse(Path(pa.__file__).read_text())
    guarded = next(n for n in tree.body if isinstance(n, ast.If) and ast.unparse(n.test) == "TYPE_CHECKING")
    imported = {
        (node.module.split(".")[0], alias.name)
        for node in guarded.body
        if isinstance(node, ast.ImportFrom) and node.module
        for alias in node.names
    }
    assert imported == {(module, name) for module, names in pa._EXPORTS.items() for name in names}


@pytest.mark.parametrize("name", pa.__all__)
def test_every_exported_name_resolves_to_its_subpackages_object(name: str) -> None:
    value = getattr(pa, name)
    if name in pa._HOME:
        assert value is getattr(__import__(f"passive_assoc.{pa._HOME[name]}", fromlist=[name]), name)


def test_subpackages_are_attributes_and_unknown_names_are_not() -> None:
    assert pa.simulation.static_scan is not None and pa.evidence is not None
    assert {"simulation", "StaticAssociator", "InitiatedTrack"} <= set(dir(pa))
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        _ = pa.nope  # type: ignore[attr-defined]


def test_the_top_level_help_imports_no_command() -> None:
    """``passive-assoc --help`` builds the commands' options only for the command that runs,
    so the list of commands needs none of their modules (it took 2 s with them)."""
    code = (
        "import sys\nfrom passive_assoc.cli import main\ntry:\n    main(['--help'])\nexcept SystemExit:\n    pass\n"
        "print(sorted(m for m in sys.modules if m.startswith(('passive_assoc.commands', "
        "'passive_assoc.experiments', 'scipy', 'numpy'))), file=sys.stderr)"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120, check=True)
    assert "associate-tracks" in done.stdout and "reproduce" in done.stdout
    assert done.stderr.strip() == "[]", done.stderr
