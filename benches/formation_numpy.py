"""The modified baseline least-distance method (METHODS §3 steps 1–5) in NumPy: the comparator
for ``passive_assoc.locate_formation``.

Written the way a competent NumPy user would: step 1 for all baseline reports at once (every
intersection of every baseline line with every line of a sensor, with their supports and
range tests, as (n_baseline, n_k) arrays), then a Python loop over the baseline reports in
which the nearest-point search and the cluster radii are vectorised over all reference points.
Settings are the paper's defaults: the simple-support Dempster reading ``m = 1 − Π(1 − s_k)``,
full lines, reference subset = the smallest (ties by the lowest sensor index), the planar
cluster radius over all ``M(M−1)/2`` intersections of the chosen lines (``n`` = the number of
non-parallel pairs), each baseline report decided on its own.

Tests import :func:`locate_formation_numpy` by path; ``python benches/formation_numpy.py``
times it on the paper scene and on a 5-sensor, 200-emitter scene, and the library beside it
(``passive_assoc.locate_formation``, same inputs, same run) with the ratio.

    python benches/formation_numpy.py [--repeat 5] [--seed 1]
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable, Sequence
from functools import partial
from typing import Any

import numpy as np
import passive_assoc as pa
from numpy.typing import ArrayLike, NDArray
from passive_assoc.simulation import FormationScene, formation_scene, paper_formation_scene

# Two lines whose direction cross product is below this are parallel: no intersection.
PARALLEL = 1e-12

Float = NDArray[np.float64]


def intersect(sa: Float, ua: Float, sb: Float, ub: Float) -> tuple[Float, NDArray[np.bool_]]:
    """Intersections of the lines ``sa + r ua`` and ``sb + r ub`` (broadcast over leading axes).

    Returns the points (..., 2) and whether the lines are not parallel; the point is
    ``sa + ra ua``, the same expression (so the same rounding) as the loop form of eqs. 1–2.
    """
    cross = ua[..., 0] * ub[..., 1] - ua[..., 1] * ub[..., 0]
    ok = np.abs(cross) >= PARALLEL
    w = sb - sa
    ra = (w[..., 0] * ub[..., 1] - w[..., 1] * ub[..., 0]) / np.where(ok, cross, 1.0)
    return sa + ra[..., None] * ua, ok


def support(fa: Float, fb: Float, std: Float) -> Float:
    """``m(assoc) = 1 − Π_k (1 − s_k)`` with eq. 3's ``s_k`` (both reports have std σ_k)."""
    s = np.exp(-((fa - fb) ** 2) / (2 * (2 * std**2)))
    out: Float = 1 - np.prod(1 - s, axis=-1)
    return out


def _subsets(
    pos: Float,
    dirs: list[Float],
    attrs: list[Float] | None,
    std: Float,
    eta: float,
    r_max: float,
    baseline: int,
) -> dict[int, tuple[Float, NDArray[np.bool_]]]:
    """Step 1 for every baseline report at once: per other sensor k, the (n_b, n_k, 2)
    intersections and whether each survives (non-parallel, within R_max of both, support ≥ η)."""
    out = {}
    for k in range(len(dirs)):
        if k == baseline:
            continue
        points, ok = intersect(pos[baseline], dirs[baseline][:, None, :], pos[k], dirs[k][None, :, :])
        ok &= np.hypot(*np.moveaxis(points - pos[baseline], -1, 0)) <= r_max
        ok &= np.hypot(*np.moveaxis(points - pos[k], -1, 0)) <= r_max
        if attrs is not None:
            ok &= support(attrs[baseline][:, None, :], attrs[k][None, :, :], std) >= eta
        out[k] = (points, ok)
    return out


def _radii(pos: Float, dirs: list[Float], choice: NDArray[np.int64]) -> Float:
    """Eq. 6 over all pairwise intersections of each candidate's lines: choice (n_c, M) -> (n_c,)."""
    m = choice.shape[1]
    chosen = np.stack([dirs[s][choice[:, s]] for s in range(m)], axis=1)  # (n_c, M, 2)
    ia, ib = np.triu_indices(m, 1)
    points, ok = intersect(pos[ia], chosen[:, ia], pos[ib], chosen[:, ib])  # (n_c, P, 2)
    n = ok.sum(axis=1)
    centre = np.where(ok[..., None], points, 0.0).sum(axis=1) / n[:, None]
    spread = np.where(ok[..., None], (points - centre[:, None, :]) ** 2, 0.0).sum(axis=(1, 2))
    radius: Float = np.sqrt(spread / n)
    return radius


def _best(
    j: int, baseline: int, found: dict[int, tuple[Float, NDArray[np.bool_]]], pos: Float, dirs: list[Float]
) -> tuple[NDArray[np.int64], float] | None:
    """Steps 2–4 for baseline report j: the chosen line per sensor and its radius, or None."""
    members = {k: np.flatnonzero(ok[j]) for k, (_, ok) in found.items()}
    if any(len(rows) == 0 for rows in members.values()):
        return None
    ref = min(members, key=lambda k: (len(members[k]), k))
    ref_points = found[ref][0][j, members[ref]]
    choice = np.empty((len(ref_points), len(dirs)), dtype=np.int64)
    choice[:, baseline], choice[:, ref] = j, members[ref]
    for k, rows in members.items():
        if k != ref:
            cand = found[k][0][j, rows]
            dist = np.hypot(cand[None, :, 0] - ref_points[:, None, 0], cand[None, :, 1] - ref_points[:, None, 1])
            choice[:, k] = rows[np.argmin(dist, axis=1)]  # first minimum, as the loop form
    radius = _radii(pos, dirs, choice)
    best = int(np.argmin(radius))
    return choice[best], float(radius[best])


def locate_formation_numpy(
    azimuth: Sequence[ArrayLike],
    sensor_positions: ArrayLike,
    attributes: Sequence[ArrayLike] | None = None,
    attribute_std: ArrayLike | None = None,
    eta: float = 0.6,
    r_max: float = 200e3,
    baseline: int = 0,
) -> tuple[NDArray[np.int64], Float]:
    """Associate every report of the baseline sensor (METHODS §3, paper defaults).

    Parameters
    ----------
    azimuth : sequence of array_like, one (n_s,) per sensor
        Bearings, radians.
    sensor_positions : array_like, shape (M, 2)
    attributes : sequence of array_like, one (n_s, K) per sensor, optional
        None: azimuth only (no attribute gate).
    attribute_std : array_like, shape (K,)
        σ_k; required with ``attributes``.
    eta, r_max, baseline : float, float, int
        Attribute gate, largest range (m), baseline sensor.

    Returns
    -------
    chosen : ndarray of int, shape (n_baseline, M)
        Report index chosen at each sensor, −1 where the baseline report is not associated;
        column ``baseline`` holds the report's own index.
    radius : ndarray of float, shape (n_baseline,)
        The chosen candidate's cluster radius, NaN when not associated.
    """
    pos = np.asarray(sensor_positions, dtype=np.float64)
    az = [np.asarray(a, dtype=np.float64) for a in azimuth]
    dirs = [np.stack([np.cos(a), np.sin(a)], axis=-1) for a in az]
    attrs = None if attributes is None else [np.asarray(a, dtype=np.float64) for a in attributes]
    if attrs is not None and attribute_std is None:
        raise ValueError("attribute_std: required when attributes are given")
    std = np.asarray(attribute_std if attribute_std is not None else [], dtype=np.float64)
    found = _subsets(pos, dirs, attrs, std, eta, r_max, baseline)
    n_b = len(az[baseline])
    chosen = np.full((n_b, len(az)), -1, dtype=np.int64)
    chosen[:, baseline] = np.arange(n_b)
    radius = np.full(n_b, np.nan)
    for j in range(n_b):  # each baseline report on its own (step 5)
        best = _best(j, baseline, found, pos, dirs)
        if best is not None:
            chosen[j], radius[j] = best
    return chosen, radius


def per_sensor(scene: FormationScene) -> tuple[list[Float], Float, list[Float], Float]:
    """A scene's bearings and attributes split by sensor, its 2-D positions and σ_k."""
    m = scene.measurements
    names = list(scene.attribute_std)
    table = np.column_stack([m.attributes[name] for name in names])
    rows = [np.flatnonzero(m.sensor == s) for s in range(scene.sensors.n_sensors)]
    std = np.array([scene.attribute_std[name] for name in names])
    return [m.azimuth[r] for r in rows], scene.sensors.positions[:, :2], [table[r] for r in rows], std


def best_of(repeat: int, run: Callable[[], Any]) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return min(times)


def _library_call(scene: FormationScene, gated: bool) -> Callable[[], Any]:
    """``passive_assoc`` on the same inputs: a :class:`~passive_assoc.FormationLocator`
    configured once, as a user locating many snapshots would (``attributes=[]``: azimuth only)."""
    locator = pa.FormationLocator(attributes=None if gated else [], attribute_std=dict(scene.attribute_std))
    return lambda: locator.locate(scene.measurements, scene.sensors)


def time_scene(label: str, scene: FormationScene, repeat: int) -> None:
    az, pos, attrs, std = per_sensor(scene)
    for gated in (True, False):
        inputs = attrs if gated else None
        numpy_s = best_of(repeat, partial(locate_formation_numpy, az, pos, inputs, std))
        line = f"{label:<38} {'joint' if gated else 'azimuth only':<13} numpy {numpy_s * 1e3:9.2f} ms"
        lib_s = best_of(repeat, _library_call(scene, gated))
        print(f"{line}   passive_assoc {lib_s * 1e3:9.3f} ms   ratio {numpy_s / lib_s:7.1f}x")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    # The figures this prints are recorded in docs/performance.md, not here.
    time_scene("paper scene (3 x 6, 1 deg, paper)", paper_formation_scene(args.seed, 1.0), args.repeat)
    large = formation_scene(args.seed, n_sensors=5, n_emitters=200)
    time_scene(f"formation_scene (5 x 200, {len(large.measurements)} rows)", large, args.repeat)


if __name__ == "__main__":
    main()
