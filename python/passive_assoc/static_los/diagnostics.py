"""How a static association got its answer (METHODS §2): the enumeration's counts and what
the chosen method reports, as typed records of :attr:`StaticAssociation.diagnostics`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from .._core import Candidates

__all__ = ["IntensityDiagnostics", "IntensityLevel", "SolverDiagnostics", "StaticDiagnostics", "stage_counts"]


@dataclass(frozen=True)
class IntensityLevel:
    """One intensity level of the paper's search (eq. 11–13): its candidates, the start
    points H, the chains run from them and the points the vote confirmed."""

    intensity: int
    candidates: int
    starts: int
    chains: int
    confirmed: int


@dataclass(frozen=True)
class IntensityDiagnostics:
    """The intensity method's search: the valid-airspace radius d (NaN when the airspace rule
    is off), the ghosts it dropped, the chains run, and each level from the highest."""

    airspace_radius: float
    ghosts_dropped: int
    chains: int
    levels: list[IntensityLevel]


@dataclass(frozen=True)
class SolverDiagnostics:
    """An S-D solve (Lagrangian or exact): the chosen tuples' total cost, the dual bound,
    the relative gap between them, iterations (Lagrangian) or nodes (exact), and whether
    optimality was proven."""

    primal_cost: float
    dual_bound: float
    gap: float
    iterations: int
    optimal: bool


@dataclass(frozen=True)
class StaticDiagnostics:
    """What one scan's association did.

    Attributes
    ----------
    method : str
        The method that chose the targets.
    candidates : int
        Gated candidate tuples enumerated.
    stage_counts : dict of str to int
        The enumeration's partial tuples tested and pruned per depth (:func:`stage_counts`).
    priced_candidates : int or None
        Candidates left after the region prior (None without ``target_density``).
    solver : SolverDiagnostics or None
        The S-D solve (``"lagrangian"``, ``"exact"``), else None.
    intensity : IntensityDiagnostics or None
        The intensity search (``"intensity"``), else None.
    """

    method: str
    candidates: int
    stage_counts: dict[str, int]
    priced_candidates: int | None = None
    solver: SolverDiagnostics | None = None
    intensity: IntensityDiagnostics | None = None


def stage_counts(candidates: Candidates) -> dict[str, int]:
    """The enumeration's partial tuples tested and pruned per depth k (``tested_k``,
    ``pruned_k`` for k = 2..S), those skipped by the bearing window or cut by the attribute
    gate, and the ``final`` count."""
    stages = candidates.stages
    counts: dict[str, int] = {}
    for k in range(2, len(stages.tested)):
        counts[f"tested_{k}"] = int(stages.tested[k])
        counts[f"pruned_{k}"] = int(stages.pruned[k])
    counts["windowed_out"] = int(stages.windowed_out)
    counts["attribute_pruned"] = int(stages.attribute_pruned)
    counts["final"] = int(stages.candidates)
    return counts


def intensity_diagnostics(out: Any) -> IntensityDiagnostics:
    """The core's intensity-search output as :class:`IntensityDiagnostics`."""
    levels = [
        IntensityLevel(int(v.intensity), int(v.candidates), int(v.starts), int(v.chains), int(v.confirmed))
        for v in out.levels
    ]
    return IntensityDiagnostics(float(out.airspace_radius), int(out.ghosts_dropped), int(out.chains), levels)
