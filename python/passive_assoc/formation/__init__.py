"""Passive location of formation targets with emitter attributes (METHODS §3, paper 004):
the modified baseline least-distance method with a Dempster-Shafer attribute gate."""

from __future__ import annotations

from .locator import FormationDiagnostics, FormationLocator, FormationResult, locate_formation

__all__ = ["FormationDiagnostics", "FormationLocator", "FormationResult", "locate_formation"]
