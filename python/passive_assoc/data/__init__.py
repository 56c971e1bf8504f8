"""The data model: measurements (:class:`MeasurementTable`) and the sensors that made them
(:class:`SensorNetwork`). Depends on nothing else in the package."""

from __future__ import annotations

from .measurements import ATTRIBUTE_PREFIX, MeasurementTable
from .sensors import COINCIDENCE_TOLERANCE, SensorNetwork

__all__ = ["ATTRIBUTE_PREFIX", "COINCIDENCE_TOLERANCE", "MeasurementTable", "SensorNetwork"]
