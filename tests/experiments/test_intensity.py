"""The `reproduce intensity` experiment's own pieces."""

from __future__ import annotations

from collections.abc import Callable

import passive_assoc as pa
from passive_assoc.experiments.intensity import bayes_map, scenario_prior
from passive_assoc.simulation import StaticScan


def test_bayes_bound_recovers_a_noiseless_scan(noiseless_static_scan: Callable[..., StaticScan]) -> None:
    scan = noiseless_static_scan(4, n_targets=6)
    assert bayes_map(scan, time_limit=5.0) == {"accuracy": 1.0, "truth_beaten": 0.0}


def test_every_method_with_the_prior_recovers_a_noiseless_scan(
    noiseless_static_scan: Callable[..., StaticScan],
) -> None:
    scan = noiseless_static_scan(4, n_targets=6)
    settings = scenario_prior(scan)
    for method in ("intensity", "lagrangian", "exact"):
        result = pa.associate_static(scan.measurements, scan.sensors, method, **settings)
        found = {tuple(row) for row in result.rows.tolist()}
        assert all(tuple(t) in found for t in scan.true_tuples.tolist()), method
