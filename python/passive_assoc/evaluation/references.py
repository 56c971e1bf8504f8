"""Evaluation against simulated truth: bounds and perfect-association references that every
experiment prints beside its own figures (METHODS §6)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from ..estimation import FitResult, crlb, fit_ml
from ..simulation import Scenario


def target_crlbs(scenario: Scenario) -> NDArray[np.float64]:
    """CRLB of every target's initial state from its own (true) measurements.

    Returns
    -------
    ndarray, shape (n_targets, D, D)
    """
    m = scenario.measurements
    return np.stack(
        [
            crlb(
                m.sensor[rows],
                m.time[rows],
                scenario.sensors,
                scenario.true_states[k],
                t0=scenario.t0,
                sensor_position=None if m.sensor_position is None else m.sensor_position[rows],
                sigma_azimuth=None if m.sigma_azimuth is None else m.sigma_azimuth[rows],
                sigma_elevation=None if m.sigma_elevation is None else m.sigma_elevation[rows],
            )
            for k, rows in enumerate(scenario.true_groups())
        ]
    )


def perfect_association_fit(scenario: Scenario, n_threads: int | None = None) -> FitResult:
    """ML fit of every target from exactly its own measurements: the reference an association
    method is judged against ("RMS with perfect association")."""
    return fit_ml(scenario.measurements, scenario.sensors, scenario.true_groups(), t0=scenario.t0, n_threads=n_threads)
