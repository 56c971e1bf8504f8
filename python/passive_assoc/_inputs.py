"""The checks and array extraction every entry point into the core shares: a
(MeasurementTable, SensorNetwork) pair, validated once, as the columns the core takes."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from .data import MeasurementTable, SensorNetwork


class CoreColumns(NamedTuple):
    """Positional arguments of the core's measurement functions, in their order."""

    sensor: NDArray[np.int64]
    time: NDArray[np.float64]
    azimuth: NDArray[np.float64]
    elevation: NDArray[np.float64]
    sensor_positions: NDArray[np.float64]
    sigma_azimuth: NDArray[np.float64]
    sigma_elevation: NDArray[np.float64]


def check_network(sensors: object) -> SensorNetwork:
    if not isinstance(sensors, SensorNetwork):
        raise TypeError(f"sensors: expected a SensorNetwork, got {type(sensors).__name__}")
    return sensors


def core_columns(measurements: object, sensors: object) -> CoreColumns:
    """Type-check the pair, refuse an empty table or one that does not match the network, and
    return the columns (elevation zero-filled for a 2-D network, whose core ignores it)."""
    if not isinstance(measurements, MeasurementTable):
        raise TypeError(f"measurements: expected a MeasurementTable, got {type(measurements).__name__}")
    network = check_network(sensors)
    if len(measurements) == 0:
        raise ValueError("measurements: the table is empty")
    measurements.validate_against(network)
    elevation = np.zeros(len(measurements)) if network.ndim == 2 else measurements.elevation
    return CoreColumns(
        measurements.sensor,
        measurements.time,
        measurements.azimuth,
        np.ascontiguousarray(elevation),
        network.positions,
        network.sigma_azimuth,
        network.sigma_elevation,
    )
