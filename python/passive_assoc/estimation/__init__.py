"""Estimation: batched ML fitting of angle measurements and the Cramér-Rao bound (METHODS §1
"Final estimate", §6); batched Kalman filtering of measurements into local tracks (§4, §5);
one extended Kalman filter step on an angle report (the built-in tracker's)."""

from __future__ import annotations

from .angle_ekf import AngleInnovation, angle_innovation, cv_predict, ekf_update
from .fitting import TERMINATION_NAMES, FitResult, crlb, fisher_and_crlb, fit_ml
from .kalman import KalmanFilter, KalmanResult

__all__ = [
    "TERMINATION_NAMES",
    "FitResult",
    "crlb",
    "fisher_and_crlb",
    "fit_ml",
    "KalmanFilter",
    "KalmanResult",
    "AngleInnovation",
    "angle_innovation",
    "cv_predict",
    "ekf_update",
]
