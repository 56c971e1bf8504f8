"""Estimation: batched ML fitting of angle measurements and the Cramér-Rao bound (METHODS §1
"Final estimate", §6); batched Kalman filtering of measurements into local tracks (§4, §5)."""

from __future__ import annotations

from .fitting import TERMINATION_NAMES, FitResult, crlb, fisher_and_crlb, fit_ml
from .kalman import KalmanFilter, KalmanResult

__all__ = ["TERMINATION_NAMES", "FitResult", "crlb", "fisher_and_crlb", "fit_ml", "KalmanFilter", "KalmanResult"]
