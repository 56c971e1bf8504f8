"""Radar/ESM track association of maneuvering targets with wavelets and fuzzy factors
(METHODS §5, paper 003)."""

from __future__ import annotations

from .coarse import CoarseGate, approximation_operator, coarse_gate, coefficients

__all__ = ["CoarseGate", "approximation_operator", "coarse_gate", "coefficients"]
