"""Moving sensors: where each platform was over time, and its position at a report's time.

A :class:`SensorTrack` holds fixes ``(sensor, time, x, y, z)``; between two fixes of a sensor
the platform moves in a straight line at constant speed (linear interpolation), so two fixes
are a constant-velocity leg and more are waypoints. A report outside its sensor's fixes is an
error (no extrapolation); a sensor with one fix stays there. :meth:`SensorTrack.attach`
writes each report's sensor position into a :class:`MeasurementTable` (its
``sensor_position`` column), which every method then uses in place of the network's fixed
position; sensors without fixes keep theirs.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import as_float_array, as_int_array, readonly, require_finite
from ._io import parse_column, read_csv_text, zip_columns
from .geodetic import LocalFrame, place_columns
from .measurement_files import TimeOrigin, canonical_name, parse_times
from .measurements import MeasurementTable

__all__ = ["SensorTrack"]

_COLUMNS = ("sensor", "time", "x", "y", "z", "lat", "lon", "alt")


@dataclass(frozen=True, eq=False)
class SensorTrack:
    """Fixes of moving sensors, interpolated linearly in time.

    Parameters
    ----------
    sensor : array_like of int, shape (M,)
        The sensor of each fix (the network's index, >= 0).
    time : array_like of float, shape (M,)
        Seconds, finite; two fixes of one sensor may not share a time.
    position : array_like of float, shape (M, 3) or (M, 2)
        Metres, in the network's frame; ``(M, 2)`` gets z = 0.

    Examples
    --------
    >>> track = SensorTrack.constant_velocity([0], [[0.0, 0.0]], [[200.0, 0.0]], 0.0, 600.0)
    >>> track.position_at([0, 0], [0.0, 30.0])[:, 0].tolist()
    [0.0, 6000.0]
    """

    sensor: NDArray[np.int64]
    time: NDArray[np.float64]
    position: NDArray[np.float64]

    def __post_init__(self) -> None:
        sensor = as_int_array("sensor", self.sensor, ndim=1)
        time = as_float_array("time", self.time, ndim=1)
        position = as_float_array("position", self.position, ndim=2)
        if position.shape[1] == 2:
            position = np.column_stack([position, np.zeros(len(position))])
        if position.shape[1] != 3:
            raise ValueError(f"position: expected shape (M, 3) or (M, 2), got {position.shape}")
        if not len(sensor) == len(time) == len(position):
            raise ValueError(f"time, position: {len(time)} times and {len(position)} positions for {len(sensor)} fixes")
        if len(sensor) == 0:
            raise ValueError("sensor: a sensor track needs at least one fix")
        if (sensor < 0).any():
            raise ValueError(f"sensor: indices must be >= 0, got {int(sensor.min())}")
        require_finite("time", time)
        require_finite("position", position)
        order = np.lexsort((time, sensor))
        sensor, time, position = sensor[order], time[order], position[order]
        repeat = (np.diff(sensor) == 0) & (np.diff(time) == 0)
        if repeat.any():
            k = int(np.flatnonzero(repeat)[0])
            raise ValueError(f"time: sensor {sensor[k]} has two fixes at time {float(time[k])!r}")
        object.__setattr__(self, "sensor", readonly(sensor))
        object.__setattr__(self, "time", readonly(time))
        object.__setattr__(self, "position", readonly(position))

    # ------------------------------------------------------------------ constructors
    @classmethod
    def constant_velocity(
        cls, sensors: ArrayLike, start: ArrayLike, velocity: ArrayLike, t_start: float, t_end: float
    ) -> SensorTrack:
        """Each of ``sensors`` moving from ``start`` (its position at ``t_start``) at
        ``velocity`` (m/s) until ``t_end``."""
        ids = as_int_array("sensors", sensors, ndim=1)
        p0 = as_float_array("start", start, ndim=2)
        v = as_float_array("velocity", velocity, ndim=2)
        if p0.shape != v.shape or len(p0) != len(ids):
            raise ValueError(f"start, velocity: expected one row per sensor ({len(ids)}), got {p0.shape}, {v.shape}")
        if not float(t_end) > float(t_start):
            raise ValueError(f"t_end: must be after t_start = {t_start!r}, got {t_end!r}")
        dt = float(t_end) - float(t_start)
        return cls(
            np.repeat(ids, 2),
            np.tile([float(t_start), float(t_end)], len(ids)),
            np.stack([p0, p0 + v * dt], axis=1).reshape(-1, p0.shape[1]),
        )

    @classmethod
    def from_csv(
        cls, path: str | os.PathLike[str], *, time_origin: TimeOrigin = None, frame: LocalFrame | None = None
    ) -> SensorTrack:
        r"""Read fixes from a CSV file with columns ``sensor``, ``time`` (seconds or ISO 8601,
        as in :meth:`MeasurementTable.from_csv`), ``x``, ``y`` [, ``z``], or ``lat``, ``lon``
        [, ``alt``] placed in ``frame`` (the network's: ``SensorNetwork.frame``); the aliases
        ``sensor_id``, ``t``, ``timestamp``, ``latitude``, ``longitude``, ``altitude`` are
        read. Errors name the file.

        >>> import tempfile, pathlib
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "platform.csv"
        >>> _ = path.write_text("sensor_id,t,x,y\n0,0,0,0\n0,100,1000,0\n")
        >>> SensorTrack.from_csv(path).position_at(0, 25.0).tolist()
        [250.0, 0.0, 0.0]
        """
        header, rows = read_csv_text(path)
        aliases = {"latitude": "lat", "longitude": "lon", "altitude": "alt"}
        names = [aliases.get(name.strip().lower(), canonical_name(name, _COLUMNS)) for name in header]
        columns: dict[str, Any] = {}
        for name, values in zip_columns(names, rows):
            if name == "time":
                columns[name] = parse_times(path, values, time_origin)
            elif name in _COLUMNS:
                columns[name] = parse_column(path, name, values, integer=name == "sensor")
        where = repr(os.fspath(path))
        if "lat" in columns and frame is None:
            raise ValueError(f"frame: {where} gives fixes as latitude and longitude; pass the network's frame")
        columns, _ = place_columns(columns, frame, prefix="", planar=False, source=where)
        missing = [name for name in _COLUMNS[:4] if name not in columns]
        if missing:
            raise ValueError(f"{where}: missing column(s) {missing} of a sensor track (got {header})")
        xyz = [columns["x"], columns["y"], columns.get("z", np.zeros(len(columns["x"])))]
        try:
            return cls(columns["sensor"], columns["time"], np.column_stack(xyz))
        except ValueError as err:
            raise ValueError(f"{where}: {err}") from None

    # ------------------------------------------------------------------ queries
    @property
    def sensors(self) -> NDArray[np.int64]:
        """The sensors that have fixes, ascending."""
        return np.unique(self.sensor)

    def position_at(self, sensor: ArrayLike, time: ArrayLike) -> NDArray[np.float64]:
        """Positions ``(..., 3)`` of ``sensor`` at ``time`` (broadcast), interpolated.

        Raises
        ------
        ValueError
            A sensor without fixes, or a time outside its fixes (naming the first such entry).
        """
        idx = as_int_array("sensor", sensor)
        t = as_float_array("time", time)
        require_finite("time", t)
        idx, t = np.broadcast_arrays(idx, t)
        out = np.empty((*idx.shape, 3))
        flat_idx, flat_t, flat_out = idx.ravel(), t.ravel(), out.reshape(-1, 3)
        for j in np.unique(flat_idx).tolist():
            mine = np.flatnonzero(flat_idx == j)
            fixes = np.flatnonzero(self.sensor == j)
            if not fixes.size:
                raise ValueError(f"sensor: {j} has no fixes in this sensor track (sensors {self.sensors.tolist()})")
            times, points = self.time[fixes], self.position[fixes]
            when = flat_t[mine]
            outside = (when < times[0]) | (when > times[-1])
            if outside.any():
                k = int(mine[np.flatnonzero(outside)[0]])
                raise ValueError(
                    f"time: entry {k} ({float(flat_t[k])!r} s) is outside sensor {j}'s fixes "
                    f"[{float(times[0])!r}, {float(times[-1])!r}] s; a sensor track is not extrapolated"
                )
            for c in range(3):
                flat_out[mine, c] = np.interp(when, times, points[:, c])
        return out

    def attach(self, measurements: MeasurementTable) -> MeasurementTable:
        """``measurements`` with each report's sensor position at its time (the
        ``sensor_position`` column) for every sensor this track has; the other rows keep
        theirs (NaN: the network's fixed position). A 2-D (bearing-only) table takes the
        platform's horizontal position: its height is dropped, as a 2-D network's."""
        if not isinstance(measurements, MeasurementTable):
            raise TypeError(f"measurements: expected a MeasurementTable, got {type(measurements).__name__}")
        old = measurements.sensor_position
        position = np.full((len(measurements), 3), np.nan) if old is None else old.copy()
        moving = np.isin(measurements.sensor, self.sensors)
        position[moving] = self.position_at(measurements.sensor[moving], measurements.time[moving])
        if measurements.ndim == 2:  # bearings only: the platform on the plane (its height dropped)
            position[moving, 2] = 0.0
        columns = measurements.to_arrays()
        for k, name in enumerate(("sensor_x", "sensor_y", "sensor_z")[: measurements.ndim]):
            columns[name] = position[:, k]
        return MeasurementTable.from_columns(columns, check_angle_unit=False)
