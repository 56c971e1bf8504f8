"""Estimation from angle measurements: batched ML fitting and the Cramér-Rao bound
(METHODS §1 "Final estimate", §6)."""

from __future__ import annotations

from .fitting import TERMINATION_NAMES, FitResult, crlb, fisher_and_crlb, fit_ml

__all__ = ["TERMINATION_NAMES", "FitResult", "crlb", "fisher_and_crlb", "fit_ml"]
