"""The data model: measurements (:class:`MeasurementTable`), the sensors that made them
(:class:`SensorNetwork`) and their motion (:class:`SensorTrack`), and track states
(:class:`TrackTable`) with the state-vector conventions (:mod:`.conventions`). Depends on
nothing else in the package."""

from __future__ import annotations

from .conventions import (
    covariance_from_interleaved,
    covariance_to_interleaved,
    from_interleaved,
    interleaved_order,
    to_interleaved,
)
from .geodetic import LocalFrame
from .measurements import ATTRIBUTE_PREFIX, MeasurementTable
from .sensor_tracks import SensorTrack
from .sensors import COINCIDENCE_TOLERANCE, SensorNetwork
from .tracks import SYMMETRY_TOLERANCE, TrackTable

__all__ = [
    "ATTRIBUTE_PREFIX",
    "COINCIDENCE_TOLERANCE",
    "LocalFrame",
    "MeasurementTable",
    "SensorNetwork",
    "SensorTrack",
    "SYMMETRY_TOLERANCE",
    "TrackTable",
    "interleaved_order",
    "to_interleaved",
    "from_interleaved",
    "covariance_to_interleaved",
    "covariance_from_interleaved",
]
