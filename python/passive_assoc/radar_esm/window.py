"""The covariance of a filtered position sequence over a window, cross-time terms included
(METHODS §5 step 2: "Σ the tracks' position covariances over the window").

A Kalman filter's errors are correlated from scan to scan: with ``e_k = x_k − x̂_k|k``,

    e_k = A_k e_{k−1} + (noise independent of e_{k−1}),   A_k = (I − K_k H) F_k = P_k|k P_k|k−1⁻¹ F_k,

so ``Cov(e_k, e_j) = A_k ⋯ A_{j+1} P_j|j`` for k > j. The per-scan covariances ``P_k|k`` are
in the track table; ``P_k|k−1 = F P_{k−1|k−1} Fᵀ + Q`` needs only the filter's motion model,
here the constant-acceleration model with white-jerk density q of
:class:`~passive_assoc.KalmanFilter` (METHODS §5 step 1), so the whole window's covariance is
rebuilt from the table and q — exactly, for tracks that filter made. The wavelet
approximation coefficients are long weighted averages of the window, so these terms dominate
their variance: without them the gate keeps far fewer true pairs than nominal
(docs/experiments.md, wavelet).

:class:`RollingWindow` keeps, per track, the position covariance of the last ``cap`` scans and
advances it one scan at a time (one batched product per scan), so a run of K scans costs
O(K · cap) small products per track instead of O(K · cap²).
"""

from __future__ import annotations

import functools

import numpy as np
from numpy.typing import NDArray

from .scans import AlignedTracks

__all__ = ["RollingWindow", "ca_model", "coefficient_covariance", "filter_transitions"]


@functools.lru_cache(maxsize=256)
def ca_model(dt: float, ndim: int, process_noise: float) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """F and Q of the constant-acceleration model over ``dt`` seconds, block state order
    ``[positions, velocities, accelerations]`` (as :class:`~passive_assoc.KalmanFilter`):
    white jerk of density ``process_noise`` on every axis, discretised exactly. Cached (a
    scan grid repeats one dt) and read-only."""
    f1 = np.array([[1.0, dt, dt * dt / 2.0], [0.0, 1.0, dt], [0.0, 0.0, 1.0]])
    q1 = process_noise * np.array(
        [
            [dt**5 / 20.0, dt**4 / 8.0, dt**3 / 6.0],
            [dt**4 / 8.0, dt**3 / 3.0, dt**2 / 2.0],
            [dt**3 / 6.0, dt**2 / 2.0, dt],
        ]
    )
    eye = np.eye(ndim)
    transition: NDArray[np.float64] = np.kron(f1, eye)
    noise: NDArray[np.float64] = np.asarray(np.kron(q1, eye), dtype=np.float64)
    transition.flags.writeable = noise.flags.writeable = False
    return transition, noise


def filter_transitions(tracks: AlignedTracks, times: NDArray[np.float64], process_noise: float) -> NDArray[np.float64]:
    """``A_k = P_k|k P_k|k−1⁻¹ F_k`` of every track at every scan, ``(n, K, D, D)``; zero where
    the track is absent at k or k − 1 (no predecessor: its window starts at k).

    Raises ValueError if the covariances are not a constant-acceleration state's (D = 3 ·
    ndim) or a prediction is singular.
    """
    assert tracks.covariance is not None
    n, n_scans, size, _ = tracks.covariance.shape
    ndim = tracks.ndim
    if size != 3 * ndim:
        raise ValueError(
            f"process_noise: the cross-time covariance assumes a constant-acceleration filter's "
            f"state [positions, velocities, accelerations] ({3 * ndim} values for {ndim}-D), "
            f"the tracks' covariances are {size} × {size}"
        )
    out = np.zeros((n, n_scans, size, size))
    track, scan = np.nonzero(tracks.present[:, 1:] & tracks.present[:, :-1])
    scan += 1
    if len(scan) == 0:
        return out
    # F and Q of each scan step, for all linked (track, scan) at once.
    models = [ca_model(float(times[k] - times[k - 1]), ndim, process_noise) for k in range(1, n_scans)]
    f = np.stack([m[0] for m in models])[scan - 1]
    q = np.stack([m[1] for m in models])[scan - 1]
    predicted = f @ tracks.covariance[track, scan - 1] @ np.swapaxes(f, 1, 2) + q
    try:
        # P_pred⁻¹ P_k, transposed: P_k P_pred⁻¹ (both symmetric).
        gain_free = np.linalg.solve(predicted, tracks.covariance[track, scan])
    except np.linalg.LinAlgError as error:
        raise ValueError(
            "process_noise: a track's predicted covariance is singular (zero covariances and process_noise=0?)"
        ) from error
    out[track, scan] = np.swapaxes(gain_free, 1, 2) @ f
    return out


class RollingWindow:
    """Per track, the position covariance of the last ``cap`` scans, advanced scan by scan.

    After :meth:`advance_to` scan k, :meth:`covariance` gives ``(n, ndim, L, ndim, L)``: the
    covariance of the positions at scans k − L + 1 … k (coordinate, scan), for L up to the
    track's consecutive presence (older entries are stale and never read).
    """

    def __init__(self, tracks: AlignedTracks, transitions: NDArray[np.float64], cap: int) -> None:
        assert tracks.covariance is not None
        self._transitions, self._ndim = transitions, tracks.ndim
        n, size = len(tracks), tracks.covariance.shape[2]
        # Absent scans' NaN as 0: they start no window and are never read.
        self._covariance = np.nan_to_num(tracks.covariance)
        # Cov(e_k, p_{k−l}): the full state now against the position l scans ago, (n, D, l, d);
        # the full state on the left is what the next scan's A_{k+1} multiplies.
        self._cross = np.zeros((n, size, cap, self._ndim))
        # Positions over the last cap scans, the newest last.
        self._sigma = np.zeros((n, self._ndim, cap, self._ndim, cap))
        self._at = -1  # the scan the window ends at (none yet)

    def advance_to(self, k: int) -> None:
        """Roll the window forward to end at scan k (scan by scan; k never decreases)."""
        while self._at < k:
            self._at += 1
            self._step(self._at)

    def _step(self, k: int) -> None:
        """Move from scan k − 1 to scan k."""
        d, (n, size, cap, _) = self._ndim, self._cross.shape
        old = self._cross
        cross = np.empty_like(old)
        # One (D × D)·(D × (cap − 1)·d) product per track: Cov(e_k, ·) = A_k Cov(e_{k−1}, ·).
        lagged = old[:, :, :-1, :].reshape(n, size, (cap - 1) * d)
        cross[:, :, 1:, :] = (self._transitions[:, k] @ lagged).reshape(n, size, cap - 1, d)
        cross[:, :, 0, :] = self._covariance[:, k, :, :d]
        self._cross = cross
        # newest[n, x, m, y] = Cov(p_k[x], p_m[y]), m indexing the window oldest first.
        newest = cross[:, :d, ::-1, :]
        sigma = np.empty_like(self._sigma)
        sigma[:, :, :-1, :, :-1] = self._sigma[:, :, 1:, :, 1:]
        sigma[:, :, -1, :, :] = newest.transpose(0, 1, 3, 2)
        sigma[:, :, :, :, -1] = newest.transpose(0, 3, 2, 1)
        self._sigma = sigma

    def covariance(self, rows: NDArray[np.intp], length: int) -> NDArray[np.float64]:
        """``(len(rows), ndim, L, ndim, L)`` position covariance of the last ``length`` scans."""
        window: NDArray[np.float64] = self._sigma[:, :, -length:, :, -length:][rows]
        return window


def coefficient_covariance(sigma: NDArray[np.float64], operator: NDArray[np.float64]) -> NDArray[np.float64]:
    """``C = (I ⊗ W) Σ (I ⊗ W)ᵀ`` of ``sigma`` ``(n, d, L, d, L)`` and W ``(c, L)``, as
    ``(n, d·c, d·c)`` (coordinate-major). Symmetric to rounding (the core accepts asymmetry up
    to 1e-9 of the diagonal scale and reads the lower triangle)."""
    n, d, length, _, _ = sigma.shape
    c = operator.shape[0]
    # Two batched products (einsum's path search would cost more than the work here).
    left = (operator @ sigma.reshape(n, d, length, d * length)).reshape(n, d, c, d, length)
    out: NDArray[np.float64] = (left @ operator.T).reshape(n, d * c, d * c)
    return out
