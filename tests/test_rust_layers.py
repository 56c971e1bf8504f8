"""The Rust core's modules depend downwards only (the order `rust/core/src/lib.rs` states):
every `crate::<module>` path in a file names its own top-level module or a lower layer, and
the core crate has no pyo3 in its manifest (the binding crate is the only one that does)."""

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
