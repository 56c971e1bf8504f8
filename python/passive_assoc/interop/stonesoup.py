"""Stone Soup interop (optional extra ``stonesoup``): measurements as Stone Soup
``Detection``s and back, and our initiated tracks and located targets as Stone Soup
``Track``s / ``GaussianState``s, so an initiation here can seed a Stone Soup tracker.

Conventions match. Stone Soup's bearing is ``atan2(y, x)``, counter-clockwise from +x, and its
elevation is up from the horizontal plane, as ours (METHODS §0).

* Each detection carries its sensor's measurement model: ``Cartesian2DToBearing`` in 2-D,
  ``CartesianToElevationBearing`` in 3-D, with the measurement vector ordered
  (elevation, bearing). The model is translated to where the sensor was for that report (a
  moving platform's position, ``MeasurementTable.sensor_position``, or the network's), its
  noise is the report's own variances where the table has them, else the sensor's, and it
  maps the positions of an interleaved state.
* Each detection's metadata holds the sensor index and the table row.
* Times are seconds after ``epoch`` (a ``datetime``; default 1970-01-01).
* States are interleaved, ``[x, vx, y, vy, z, vz]``, as Stone Soup's constant-velocity models
  expect (:mod:`passive_assoc.data.conventions`).
"""

from __future__ import annotations

import datetime as dt
from collections.abc import Iterable
from typing import Any

import numpy as np

from ..data import MeasurementTable, SensorNetwork
from ..data.conventions import covariance_to_interleaved, to_interleaved

__all__ = ["EPOCH", "from_detections", "target_states", "to_detections", "track_states"]

#: Time 0 of the tables' seconds.
EPOCH = dt.datetime(1970, 1, 1)


def _stonesoup() -> Any:
    try:
        import stonesoup  # noqa: F401
    except ImportError as err:
        raise ImportError("Stone Soup interop needs stonesoup: pip install 'passive-assoc[stonesoup]'") from err
    from stonesoup.models.measurement import nonlinear
    from stonesoup.types import detection, state, track

    return nonlinear, detection, state, track


def _model(position: Any, sigma_az: float, sigma_el: float, ndim: int) -> Any:
    """The bearing (2-D) or elevation-bearing (3-D) model of a sensor at ``position``."""
    nonlinear, _, _, _ = _stonesoup()
    if ndim == 2:
        return nonlinear.Cartesian2DToBearing(
            ndim_state=4,
            mapping=(0, 2),
            noise_covar=np.array([[sigma_az**2]]),
            translation_offset=np.array([[position[0]], [position[1]]]),
        )
    return nonlinear.CartesianToElevationBearing(
        ndim_state=6,
        mapping=(0, 2, 4),
        noise_covar=np.diag([sigma_el**2, sigma_az**2]),
        translation_offset=np.asarray(position, dtype=float).reshape(3, 1).copy(),
    )


def to_detections(measurements: MeasurementTable, sensors: SensorNetwork, *, epoch: dt.datetime = EPOCH) -> list[Any]:
    """One ``Detection`` per row, in row order, each with its sensor's model (for a
    constant-velocity interleaved state) and ``metadata = {"sensor": j, "row": i}``."""
    _, detection, _, _ = _stonesoup()
    from stonesoup.types.angle import Bearing, Elevation

    measurements.validate_against(sensors)
    ndim = sensors.ndim
    models = [
        _model(sensors.positions[j], sensors.sigma_azimuth[j], sensors.sigma_elevation[j], ndim)
        for j in range(sensors.n_sensors)
    ]
    own = measurements.sensor_position is not None or measurements.sigma_azimuth is not None
    own = own or measurements.sigma_elevation is not None
    sigma_az, sigma_el = measurements.report_sigmas(sensors)
    where = measurements.sensor_position
    out = []
    for i in range(len(measurements)):
        j = int(measurements.sensor[i])
        model = models[j]
        if own:  # a moving sensor or a report's own noise: the report's model
            position = sensors.positions[j] if where is None or np.isnan(where[i, 0]) else where[i]
            model = _model(position, sigma_az[i], sigma_el[i], ndim)
        if sensors.ndim == 2:
            vector = np.array([[Bearing(measurements.azimuth[i])]])
        else:
            vector = np.array([[Elevation(measurements.elevation[i])], [Bearing(measurements.azimuth[i])]])
        out.append(
            detection.Detection(
                vector,
                timestamp=epoch + dt.timedelta(seconds=float(measurements.time[i])),
                measurement_model=model,
                metadata={"sensor": j, "row": i},
            )
        )
    return out


def from_detections(detections: Iterable[Any], *, epoch: dt.datetime = EPOCH) -> MeasurementTable:
    """A table from detections made by :func:`to_detections` (or any with a ``"sensor"``
    metadata entry and a bearing or (elevation, bearing) vector), in the rows' order when
    they carry ``"row"``, else as given."""
    items = list(detections)
    if any("sensor" not in d.metadata for d in items):
        raise ValueError("detections: every detection needs metadata['sensor'] (the sensor index)")
    items.sort(key=lambda d: d.metadata.get("row", 0))
    vectors = [np.asarray(d.state_vector, dtype=float).ravel() for d in items]
    sizes = {len(v) for v in vectors}
    if not sizes <= {1} and not sizes <= {2}:
        raise ValueError(f"detections: expected bearings or (elevation, bearing) pairs, got lengths {sorted(sizes)}")
    three_d = sizes == {2}
    return MeasurementTable.from_arrays(
        np.array([int(d.metadata["sensor"]) for d in items], dtype=np.int64),
        np.array([(d.timestamp - epoch).total_seconds() for d in items]),
        np.array([v[-1] for v in vectors]),
        np.array([v[0] for v in vectors]) if three_d else None,
    )


def track_states(result: Any, *, epoch: dt.datetime = EPOCH) -> list[Any]:
    """Our initiated tracks (:class:`~passive_assoc.InitiationResult`) as Stone Soup
    ``Track``s of one ``GaussianState`` each: the interleaved constant-velocity state and
    covariance at ``t0``."""
    _, _, state, track = _stonesoup()
    timestamp = epoch + dt.timedelta(seconds=float(result.t0))
    out = []
    for k, initiated in enumerate(result.tracks):
        ndim = len(initiated.state) // 2
        mean = to_interleaved(initiated.state, ndim=ndim, blocks=2).reshape(-1, 1)
        covar = covariance_to_interleaved(initiated.covariance, ndim=ndim, blocks=2)
        out.append(track.Track([state.GaussianState(mean, covar, timestamp=timestamp)], id=str(k)))
    return out


def target_states(positions: Any, covariances: Any, *, time: float = 0.0, epoch: dt.datetime = EPOCH) -> list[Any]:
    """Located targets (positions ``(T, ndim)`` and covariances ``(T, ndim, ndim)``, e.g. of
    a :class:`~passive_assoc.StaticAssociation`) as position-only ``GaussianState``s."""
    _, _, state, _ = _stonesoup()
    timestamp = epoch + dt.timedelta(seconds=float(time))
    return [
        state.GaussianState(np.asarray(p, dtype=float).reshape(-1, 1), np.asarray(c, dtype=float), timestamp=timestamp)
        for p, c in zip(positions, covariances, strict=True)
    ]
