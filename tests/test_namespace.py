"""The public namespace: the top level keeps every name it promises its users, each
subpackage's ``__all__`` resolves, and imports between the parts point one way
(so there can be no cycle)."""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import passive_assoc as pa
import pytest

#: Top-level names the package keeps for its users (the compatibility promise).
TOP_LEVEL_NAMES = [
    "SensorTrack",
    "StaticAssociation",
    "associate_static",
    "enumerate_candidates",
    "ClosenessOptima",
    "closeness",
    "maximize_closeness",
    "FuzzyTrackInitiator",
    "InitiationResult",
    "SdAssignment",
    "assign_sd",
    "linear_assignment",
    "__version__",
    "TERMINATION_NAMES",
    "FitResult",
    "crlb",
    "fisher_and_crlb",
    "fit_ml",
    "MeasurementTable",
    "SensorNetwork",
    "PAPER_FTI_TARGETS",
    "ConstantVelocityTarget",
    "Scenario",
    "bearing_only_2d_scenario",
    "paper_fti_scenario",
    "simulate",
    "TrackTable",
    "KalmanFilter",
    "KalmanResult",
]

SUBPACKAGES = [
    "data",
    "estimation",
    "assignment",
    "fti",
    "static_los",
    "formation",
    "topology",
    "radar_esm",
    "simulation",
    "evaluation",
    "tracking",
]


def test_top_level_keeps_every_name() -> None:
    missing = [name for name in TOP_LEVEL_NAMES if name not in pa.__all__ or not hasattr(pa, name)]
    assert not missing, missing
    assert all(hasattr(pa, name) for name in pa.__all__)


def test_no_name_clashes_with_stone_soup_track() -> None:
    """``Track`` is Stone Soup's name (the interop returns its tracks): the initiator's is
    ``InitiatedTrack`` only."""
    assert not hasattr(pa, "Track")


@pytest.mark.parametrize("name", SUBPACKAGES)
def test_subpackage_all_resolves(name: str) -> None:
    module = importlib.import_module(f"passive_assoc.{name}")
    assert module.__all__, f"passive_assoc.{name} exports nothing"
    assert all(hasattr(module, item) for item in module.__all__)


#: Layers, lowest first: a module may import only from its own part or from lower layers
#: (parts on one layer do not import each other). plots sits below experiments because the
#: experiments draw their figures with it (a deferred import, matplotlib being optional).
LAYERS = [
    # cli's `from . import __version__` is _core's; evidence (Dempster-Shafer) is pure Python.
    ["_core", "_validation", "_settings", "_params", "_progress", "_warn", "__version__", "evidence", "outcome"],
    ["data"],
    ["_inputs"],
    ["estimation"],
    ["assignment", "track_association"],
    ["fti", "static_los", "formation", "topology", "radar_esm"],
    ["roles"],
    ["track_methods"],
    ["simulation"],
    ["evaluation"],
    ["tracking"],
    ["interop"],  # the Stone Soup tracker reads the built-in one's defaults
    ["distributed"],
    ["plots"],
    ["plots_data"],
    ["experiments"],
    ["commands"],
    ["cli"],
]


def _relative_imports(path: Path, package: list[str]) -> list[str]:
    """Top-level parts of ``passive_assoc`` that a module imports (relative imports only,
    deferred ones included)."""
    parts = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.ImportFrom) and node.level:
            base = package[: len(package) - node.level + 1] + (node.module.split(".") if node.module else [])
            parts += [base[1]] if len(base) > 1 else [alias.name for alias in node.names]
    return parts


def test_dependencies_point_one_way() -> None:
    layer = {part: k for k, parts in enumerate(LAYERS) for part in parts}
    root = Path(pa.__file__).parent
    wrong = []
    for path in sorted(root.rglob("*.py")):
        rel = list(path.relative_to(root).with_suffix("").parts)
        if rel == ["__init__"]:
            continue  # the namespace re-exports everything
        own = rel[0]
        package = ["passive_assoc", *rel[:-1]]
        for target in _relative_imports(path, package):
            unplaced = [part for part in (own, target) if part not in layer]
            assert not unplaced, f"{unplaced} has no layer: add it to LAYERS"
            if target != own and layer[target] >= layer[own]:
                wrong.append(f"{'.'.join(rel)} imports {target}")
    assert not wrong, wrong
