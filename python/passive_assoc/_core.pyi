"""Type stubs for the compiled core (``rust/src/py``). Use the typed wrappers in the package."""

from typing import Any

import numpy as np
from numpy.typing import NDArray

__version__: str

def fit_batch(
    sensor: NDArray[np.int64],
    time: NDArray[np.float64],
    azimuth: NDArray[np.float64],
    elevation: NDArray[np.float64],
    sensor_positions: NDArray[np.float64],
    sigma_azimuth: NDArray[np.float64],
    sigma_elevation: NDArray[np.float64],
    indices: NDArray[np.int64],
    offsets: NDArray[np.int64],
    initial: NDArray[np.float64] | None = None,
    *,
    ndim: int,
    motion: str,
    t0: float = 0.0,
    max_iter: int = 50,
    xtol: float = 1e-10,
    step_sigmas: float = 1e-6,
    max_halvings: int = 30,
    n_threads: int | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64], NDArray[np.uint32], NDArray[np.uint8]]: ...
def crlb(
    sensor_positions: NDArray[np.float64],
    sigma_azimuth: NDArray[np.float64],
    sigma_elevation: NDArray[np.float64],
    sensor_index: NDArray[np.int64],
    times: NDArray[np.float64],
    truth: NDArray[np.float64],
    *,
    ndim: int,
    motion: str,
    t0: float = 0.0,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def initiate(
    sensor: NDArray[np.int64],
    time: NDArray[np.float64],
    azimuth: NDArray[np.float64],
    elevation: NDArray[np.float64],
    sensor_positions: NDArray[np.float64],
    sigma_azimuth: NDArray[np.float64],
    sigma_elevation: NDArray[np.float64],
    pairs: NDArray[np.int64],
    spread_azimuth: NDArray[np.float64],
    spread_elevation: NDArray[np.float64],
    *,
    ndim: int,
    t0: float,
    gate: float,
    n_detect: int,
    ray_gate: float | None,
    reject_behind: bool,
    v_max: float | None,
    chi2_gate: float | None,
    one_per_scan: bool,
    merge_tol: float,
    descent_max_iter: int,
    max_candidates: int,
    n_threads: int | None,
    descent_scaling: str = "whitened",
    refine_passes: int = 2,
) -> dict[str, Any]: ...
def closeness(
    sensor: NDArray[np.int64],
    time: NDArray[np.float64],
    azimuth: NDArray[np.float64],
    elevation: NDArray[np.float64],
    sensor_positions: NDArray[np.float64],
    sigma_azimuth: NDArray[np.float64],
    sigma_elevation: NDArray[np.float64],
    spread_azimuth: NDArray[np.float64],
    spread_elevation: NDArray[np.float64],
    states: NDArray[np.float64],
    *,
    ndim: int,
    t0: float,
    n_threads: int | None = None,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]: ...
def assign_sd(
    tuples: NDArray[np.int64],
    costs: NDArray[np.float64],
    sizes: NDArray[np.int64],
    *,
    method: str = "lagrangian",
    max_iter: int = 200,
    gap_tol: float = 1e-3,
    max_nodes: int = 10_000_000,
    time_limit: float | None = 10.0,
) -> dict[str, Any]: ...
def assign_2d(costs: NDArray[np.float64]) -> tuple[NDArray[np.int64], NDArray[np.int64], float]: ...
