"""The checks every entry point into the core shares: a (MeasurementTable, SensorNetwork)
pair, validated once. The core then reads both objects' columns by attribute."""

from __future__ import annotations

from .data import MeasurementTable, SensorNetwork


def check_network(sensors: object) -> SensorNetwork:
    if not isinstance(sensors, SensorNetwork):
        raise TypeError(f"sensors: expected a SensorNetwork, got {type(sensors).__name__}")
    return sensors


def check_pair(measurements: object, sensors: object) -> tuple[MeasurementTable, SensorNetwork]:
    """Type-check the pair and refuse an empty table or one that does not match the network."""
    if not isinstance(measurements, MeasurementTable):
        raise TypeError(f"measurements: expected a MeasurementTable, got {type(measurements).__name__}")
    network = check_network(sensors)
    if len(measurements) == 0:
        raise ValueError("measurements: the table is empty")
    measurements.validate_against(network)
    return measurements, network
