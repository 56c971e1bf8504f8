"""What the user knows about where targets are: a region and a target density (a project
extension of METHODS §2).

Eq. 2 prices a candidate by the likelihood ratio of "a target at x̂" against "all clutter" at the
fitted point x̂ alone. With a prior — targets uniform over a known region at a known density
ρ (targets per m² in 2-D, per m³ in 3-D) — the posterior ratio integrates the likelihood over
where the target may be. Laplace's approximation of that integral around x̂, with P the
candidate fit's covariance and d its dimension, gives the candidate cost

    c_prior = c_eq2 − ln ρ − (d/2) ln 2π − ½ ln det P − ln Pr_N(x̂, P)(region),

the last term the prior mass of the region under the fit's Gaussian (axis-aligned box:
product of normal CDF differences over the marginal stds). A candidate far outside the region
gets +∞; one whose reports are better explained as clutter gets c_prior ≥ 0 and is never worth
choosing over leaving its reports as false alarms (the dummy costs 0), so it is dropped before
the method runs. Every method then sees the same priced candidates.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.special import ndtr

from .._core import Candidates


@dataclass(frozen=True)
class PricedCandidates:
    """The candidates a method sees after the prior: the arrays of :class:`Candidates` it
    reads, restricted to the candidates worth choosing, with their prior costs."""

    tuples: NDArray[np.int64]
    rows: NDArray[np.int64]
    positions: NDArray[np.float64]
    covariances: NDArray[np.float64]
    costs: NDArray[np.float64]
    sizes: NDArray[np.int64]


def check_region(region: Sequence[float] | None, ndim: int) -> NDArray[np.float64] | None:
    """``region`` as a (ndim, 2) array of [low, high] per axis, or None; a ValueError names
    what is wrong."""
    if region is None:
        return None
    box = np.asarray(region, dtype=float)
    if box.shape != (2 * ndim,):
        raise ValueError(
            f"region: expected {2 * ndim} numbers (xmin, xmax, ymin, ymax{', zmin, zmax' if ndim == 3 else ''}) "
            f"for a {ndim}-D network, got shape {box.shape}"
        )
    box = box.reshape(ndim, 2)
    if not np.all(np.isfinite(box)) or np.any(box[:, 1] <= box[:, 0]):
        raise ValueError(f"region: each axis needs finite low < high, got {box.tolist()}")
    return box


def prior_costs(
    candidates: Candidates, region: NDArray[np.float64] | None, target_density: float
) -> NDArray[np.float64]:
    """Every candidate's cost under the prior (+inf where the region holds no mass)."""
    positions, cov = candidates.positions, candidates.covariances
    d = positions.shape[1]
    log_mass = np.zeros(len(positions))
    if region is not None:
        sd = np.sqrt(np.einsum("nii->ni", cov))
        with np.errstate(divide="ignore", invalid="ignore"):
            z_hi, z_lo = (region[:, 1] - positions) / sd, (region[:, 0] - positions) / sd
            log_mass = np.sum(np.log(ndtr(z_hi) - ndtr(z_lo)), axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        _, log_det = np.linalg.slogdet(cov)
        cost = candidates.costs - math.log(target_density) - 0.5 * d * math.log(2 * math.pi) - 0.5 * log_det - log_mass
    return np.where(np.isfinite(cost), cost, np.inf)


def priced(candidates: Candidates, region: NDArray[np.float64] | None, target_density: float) -> PricedCandidates:
    """The candidates worth choosing under the prior (cost < 0), with their prior costs."""
    cost = prior_costs(candidates, region, target_density)
    keep = np.flatnonzero(cost < 0)
    return PricedCandidates(
        candidates.tuples[keep],
        candidates.rows[keep],
        candidates.positions[keep],
        candidates.covariances[keep],
        cost[keep],
        candidates.sizes,
    )
