"""The `reproduce intensity` experiment's own pieces."""

from __future__ import annotations

from collections.abc import Callable

import passive_assoc as pa
from passive_assoc.experiments.intensity import bayes_map
from passive_assoc.simulation import StaticScan


def test_bayes_bound_recovers_a_noiseless_scan(noiseless_static_scan: Callable[..., StaticScan]) -> None:
    scan = noiseless_static_scan(4, n_targets=6)
    cands = pa.enumerate_candidates(scan.measurements, scan.sensors)
    assert bayes_map(scan, cands, time_limit=5.0) == {"accuracy": 1.0, "truth_beaten": 0.0}
