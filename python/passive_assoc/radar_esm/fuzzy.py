"""The fine stage of METHODS §5 (paper §4): fuzzy factors and their combined similarity.

For a radar track i and an ESM track j at one scan:

* u1 = ‖a_i − a_j‖, the distance between the accelerations; σ1² = tr P_a,i + tr P_a,j;
* u2 = ‖v_i − v_j‖, between the velocities; σ2² = tr P_v,i + tr P_v,j;
* u3 = the angle between the velocity vectors in [0, π] (the wrapped heading difference in
  2-D; 0 or π in 1-D); σ3² = σψ,i² + σψ,j², the heading variance of each track to first order:
  ``σψ² = (tr P_v − v̂ᵀ P_v v̂) / ‖v‖²`` (the velocity's variance across its direction over the
  speed squared; in 2-D exactly the variance of ``atan2(vy, vx)``), and in 1-D, where there is
  no across, ``σψ² = P_v / v²`` (as if the velocity were as uncertain across as along);
* ``μ_l = exp(−τ u_l² / σ_l²)`` and ``f = Σ a_l μ_l``.

σ² is the total variance of the vector (the trace), so that ``u²/σ²`` has mean 1 for a true
pair in any dimension, as the scalar ``u²/σ²`` has in 1-D. A track at rest has no heading: its
σψ² is infinite and μ3 = 1 (no evidence either way). ``u = σ = 0`` (noiseless, identical)
gives μ = 1; ``u > 0 = σ`` gives μ = 0.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from .scans import AlignedTracks

__all__ = ["fuzzy_memberships", "membership"]

#: Indices of the state blocks in the stacked covariance.
VELOCITY, ACCELERATION = 1, 2


def membership(u_squared: NDArray[np.float64], variance: NDArray[np.float64], tau: float) -> NDArray[np.float64]:
    """``exp(−τ u²/σ²)`` elementwise, with 0/0 = 0 (μ = 1) and u²/0 = ∞ (μ = 0) for u > 0."""
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = u_squared / variance
    ratio = np.where(variance == 0.0, np.where(u_squared == 0.0, 0.0, np.inf), ratio)
    ratio = np.where(np.isinf(variance), 0.0, ratio)
    out: NDArray[np.float64] = np.exp(-tau * ratio)
    return out


def _by_scan(values: NDArray[np.float64]) -> NDArray[np.float64]:
    """(n, K, ...) → (K, n, ...)."""
    return np.swapaxes(values, 0, 1)


def _distance_factor(
    radar: NDArray[np.float64], radar_var: NDArray[np.float64], esm: NDArray[np.float64], esm_var: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """u² and σ² ``(K, n_r, n_e)`` of the distance between two vector quantities (n, K, d)
    with total variances (n, K)."""
    diff = _by_scan(radar)[:, :, None, :] - _by_scan(esm)[:, None, :, :]
    u_squared = np.einsum("kred,kred->kre", diff, diff)
    return u_squared, _by_scan(radar_var)[:, :, None] + _by_scan(esm_var)[:, None, :]


def _heading(
    velocity: NDArray[np.float64], cov: NDArray[np.float64]
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Unit direction (n, K, d) (zero at rest) and heading variance σψ² (n, K) (∞ at rest)."""
    speed_sq = np.einsum("nkd,nkd->nk", velocity, velocity)
    moving = speed_sq > 0.0
    safe = np.where(moving, speed_sq, 1.0)
    direction = np.where(moving[..., None], velocity / np.sqrt(safe)[..., None], 0.0)
    if velocity.shape[2] == 1:
        across = cov[..., 0, 0]
    else:
        along = np.einsum("nkd,nkde,nke->nk", direction, cov, direction)
        across = np.trace(cov, axis1=2, axis2=3) - along
    variance = np.where(moving, np.maximum(across, 0.0) / safe, np.inf)
    return direction, variance


def _heading_factor(radar: AlignedTracks, esm: AlignedTracks) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    assert radar.velocity is not None and esm.velocity is not None
    dir_r, var_r = _heading(radar.velocity, radar.block_covariance(VELOCITY))
    dir_e, var_e = _heading(esm.velocity, esm.block_covariance(VELOCITY))
    a, b = _by_scan(dir_r)[:, :, None, :], _by_scan(dir_e)[:, None, :, :]
    # The angle between two unit vectors, accurate near 0 and π: 2·atan2(‖a − b‖, ‖a + b‖).
    angle = 2.0 * np.arctan2(np.linalg.norm(a - b, axis=-1), np.linalg.norm(a + b, axis=-1))
    return angle**2, _by_scan(var_r)[:, :, None] + _by_scan(var_e)[:, None, :]


def fuzzy_memberships(radar: AlignedTracks, esm: AlignedTracks, tau: float) -> NDArray[np.float64]:
    """μ1 (acceleration), μ2 (velocity), μ3 (heading) of every pair at every scan,
    ``(3, K, n_radar, n_esm)``; NaN where either track is absent."""
    assert radar.acceleration is not None and esm.acceleration is not None
    assert radar.velocity is not None and esm.velocity is not None
    factors = []
    for block, r, e in (
        (ACCELERATION, radar.acceleration, esm.acceleration),
        (VELOCITY, radar.velocity, esm.velocity),
    ):
        var_r = np.trace(radar.block_covariance(block), axis1=2, axis2=3)
        var_e = np.trace(esm.block_covariance(block), axis1=2, axis2=3)
        factors.append(_distance_factor(r, var_r, e, var_e))
    factors.append(_heading_factor(radar, esm))
    out = np.stack([membership(u2, s2, tau) for u2, s2 in factors])
    absent = ~(np.swapaxes(radar.present, 0, 1)[:, :, None] & np.swapaxes(esm.present, 0, 1)[:, None, :])
    out[:, absent] = np.nan
    return out
