"""Type stubs for the compiled core (``rust/src/py``). Use the typed wrappers in the package."""

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
