"""The region / target-density prior of the static methods (docs/methods.md §2): the cost
formula, what it removes, the partition, and refused settings."""

from __future__ import annotations

import math

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.simulation import static_scan
from passive_assoc.simulation.static_los import SQUARE_X, SQUARE_Y
from passive_assoc.static_los import enumerate_candidates
from passive_assoc.static_los.prior import check_region, prior_costs
from scipy.stats import norm

REGION = (*SQUARE_X, *SQUARE_Y)
AREA = (SQUARE_X[1] - SQUARE_X[0]) * (SQUARE_Y[1] - SQUARE_Y[0])


def test_prior_cost_is_the_laplace_posterior_ratio() -> None:
    """Recomputed candidate by candidate from the formula in the module's docstring."""
    scan = static_scan(3, n_targets=6, ratio=15)
    cands = enumerate_candidates(scan.measurements, scan.sensors)
    density = 6 / AREA
    got = prior_costs(cands, check_region(REGION, 2), density)
    checked = 0
    for k in range(0, len(cands.costs), 7):
        x, p = cands.positions[k], cands.covariances[k]
        sd = np.sqrt(np.diag(p))
        mass = np.prod(
            [
                norm.cdf((hi - x[i]) / sd[i]) - norm.cdf((lo - x[i]) / sd[i])
                for i, (lo, hi) in enumerate([SQUARE_X, SQUARE_Y])
            ]
        )
        log_mass = np.log(mass) if mass > 0 else -np.inf
        want = cands.costs[k] - math.log(density) - math.log(2 * math.pi) - 0.5 * math.log(np.linalg.det(p)) - log_mass
        if np.isfinite(want):
            assert got[k] == pytest.approx(want, rel=1e-9, abs=1e-9)
            checked += 1
        else:
            assert got[k] == np.inf
    assert checked >= 10


@pytest.mark.parametrize("method", ["intensity", "lagrangian", "exact"])
def test_every_method_takes_the_prior_and_keeps_the_partition(method: str) -> None:
    """A ghost far outside the region is never reported; every row is in one target or the
    clutter set."""
    scan = static_scan(5, n_targets=8, ratio=15)
    plain = pa.associate_static(scan.measurements, scan.sensors, method)
    result = pa.associate_static(scan.measurements, scan.sensors, method, region=REGION, target_density=8 / AREA)
    assert result.diagnostics.priced_candidates < result.diagnostics.candidates
    margin = 3 * np.sqrt(np.stack([result.covariances[:, 0, 0], result.covariances[:, 1, 1]], axis=1))
    inside = (result.positions >= np.array([SQUARE_X[0], SQUARE_Y[0]]) - margin) & (
        result.positions <= np.array([SQUARE_X[1], SQUARE_Y[1]]) + margin
    )
    assert inside.all()
    used = result.rows[result.rows >= 0]
    assert len(np.unique(used)) == len(used)
    assert len(used) + len(result.clutter) == len(scan.measurements)
    assert len(plain.rows) > 0


def test_an_empty_region_leaves_every_report_as_clutter() -> None:
    scan = static_scan(5, n_targets=8, ratio=15)
    behind = (-10e3, 10e3, -60e3, -40e3)  # behind the sensors: no line of sight passes there
    result = pa.associate_static(scan.measurements, scan.sensors, "lagrangian", region=behind, target_density=1e-9)
    assert len(result.rows) == 0 and len(result.clutter) == len(scan.measurements)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        (dict(region=REGION), "target_density: needed with region"),
        (dict(region=(0.0, 1.0, 2.0), target_density=1e-8), "region: expected"),
        (dict(region=(1.0, 0.0, 0.0, 1.0), target_density=1e-8), "region: each axis needs finite low < high"),
        (dict(region=REGION, target_density=0.0), "target_density"),
        (dict(region=(0, 1, 0, 1, 0, 1), target_density=1e-8), "region: expected 4 numbers"),
    ],
)
def test_bad_prior_settings_are_refused(kwargs: dict, message: str) -> None:
    scan = static_scan(1, n_targets=3)
    with pytest.raises(ValueError, match=message):
        pa.associate_static(scan.measurements, scan.sensors, "lagrangian", **kwargs)
