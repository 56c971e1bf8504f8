"""Columnar table of angle measurements (METHODS §0).

One row per reported line of sight: ``sensor`` index, ``time`` (s), ``azimuth`` (rad),
``elevation`` (rad, NaN for a 2-D bearing-only sensor), optional per-report noise stds
``sigma_azimuth`` / ``sigma_elevation`` (rad, NaN: the sensor's), optional emitter
``attributes`` (METHODS §3), and, for simulated data only, a hidden ``truth`` label (target
index, or -1 for clutter) that no algorithm may read. The constructors take the user's angle
convention (:mod:`passive_assoc.data.angles`); the table holds radians, counter-clockwise
from east.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import as_float_array, as_int_array, readonly
from ._io import import_pandas, write_csv
from ._measurement_checks import (
    attribute_columns,
    elevation_column,
    first,
    float_column,
    noise_column,
    sensor_position_column,
    truth_column,
)
from .angles import (
    AngleUnit,
    AzimuthConvention,
    check_angle_convention,
    check_angle_range,
    from_user_angle,
    from_user_azimuth,
)
from .geodetic import LocalFrame, place_columns
from .measurement_files import TimeOrigin, read_measurement_columns, read_measurement_parquet, write_parquet
from .sensors import SensorNetwork

__all__ = ["MeasurementTable", "ATTRIBUTE_PREFIX"]

#: Column-name prefix for attributes in CSV files, DataFrames and :meth:`to_arrays`.
ATTRIBUTE_PREFIX = "attr_"
_CORE = ("sensor", "time", "azimuth", "elevation")
#: Optional per-report noise stds (radians; NaN: the sensor's value).
_NOISE = ("sigma_azimuth", "sigma_elevation")
#: Optional per-report sensor position (a moving platform; NaN: the sensor's), metres.
_PLATFORM = ("sensor_x", "sensor_y", "sensor_z")
_KNOWN = (*_CORE, *_NOISE, *_PLATFORM, "truth")
#: What the file readers take: the above, and the moving sensor's position as latitude,
#: longitude and altitude (placed in the network's frame).
_READ = (*_KNOWN, "sensor_lat", "sensor_lon", "sensor_alt")


@dataclass(frozen=True, eq=False)
class MeasurementTable:
    """Immutable, validated, columnar table of angle measurements.

    Parameters
    ----------
    sensor : array_like of int, shape (N,)
        Index of the reporting sensor, >= 0.
    time : array_like of float, shape (N,)
        Measurement time, seconds, finite.
    azimuth : array_like of float, shape (N,)
        Azimuth / bearing, radians, finite (any branch; algorithms wrap residuals).
    elevation : array_like of float, shape (N,), optional
        Elevation, radians. Either all finite (3-D) or all NaN (2-D); omitted means NaN.
    attributes : mapping of str to array_like, shape (N,), optional
        Emitter attributes (e.g. RF, PRF), each finite.
    truth : array_like of int, shape (N,), optional
        Hidden truth label: target index, or -1 for clutter. Algorithms never read it.
    sigma_azimuth, sigma_elevation : array_like of float, shape (N,), optional
        Per-report noise stds, radians, in the range a sensor's may take; NaN on a row means
        the sensor's value. Where given they replace the sensor's std row by row in every
        method (weights, gates, CRLB).
    sensor_position : array_like of float, shape (N, 3) or (N, 2), optional
        Where the reporting sensor was when it took each report, metres (a moving platform:
        see :class:`~passive_assoc.data.SensorTrack` to interpolate a platform's track at the
        report times); a row of NaN means the sensor's fixed position. Every method uses it
        in place of the network's position, the Rust core included. In files: the columns
        ``sensor_x``, ``sensor_y`` [, ``sensor_z``].
    check_angle_unit : bool
        Refuse an azimuth beyond ±2π or an elevation beyond ±π/2 (degrees given as radians:
        declare them with ``angle_unit="deg"`` in the constructors). False keeps such values.

    Notes
    -----
    Arrays are copied and made read-only. An empty table (N = 0) is valid; fitting
    functions reject empty input themselves.
    """

    sensor: NDArray[np.int64]
    time: NDArray[np.float64]
    azimuth: NDArray[np.float64]
    # ``None`` means "no elevation" and is replaced by NaN in __post_init__.
    elevation: NDArray[np.float64] = None  # type: ignore[assignment]
    attributes: Mapping[str, NDArray[np.float64]] = field(default_factory=dict)
    truth: NDArray[np.int64] | None = None
    sigma_azimuth: NDArray[np.float64] | None = None
    sigma_elevation: NDArray[np.float64] | None = None
    sensor_position: NDArray[np.float64] | None = None
    check_angle_unit: bool = field(default=True, kw_only=True)

    def __post_init__(self) -> None:
        sensor = as_int_array("sensor", self.sensor, ndim=1)
        n = sensor.shape[0]
        if (sensor < 0).any():
            i = first(sensor < 0)
            raise ValueError(f"sensor[{i}] = {sensor[i]}; sensor indices must be >= 0")
        columns: dict[str, NDArray[Any]] = {
            "sensor": sensor,
            "time": float_column("time", self.time, n),
            "azimuth": float_column("azimuth", self.azimuth, n),
            "elevation": elevation_column(self.elevation, n),
        }
        if not isinstance(self.check_angle_unit, (bool, np.bool_)):
            raise TypeError(f"check_angle_unit: expected a bool, got {self.check_angle_unit!r}")
        if self.check_angle_unit:
            check_angle_range("azimuth", columns["azimuth"])
            check_angle_range("elevation", columns["elevation"])
        planar = bool(np.isnan(columns["elevation"]).all())
        optional: dict[str, Any] = {
            "attributes": MappingProxyType(attribute_columns(self.attributes, n)),
            "truth": truth_column(self.truth, n),
            "sigma_azimuth": noise_column("sigma_azimuth", self.sigma_azimuth, n),
            "sigma_elevation": noise_column("sigma_elevation", self.sigma_elevation, n),
            "sensor_position": sensor_position_column(self.sensor_position, n, planar),
        }
        elevation_noise = optional["sigma_elevation"]
        if n and planar and elevation_noise is not None and not np.isnan(elevation_noise).all():
            raise ValueError("sigma_elevation: a 2-D table (no elevation) has no elevation noise; omit it")
        for name, value in columns.items():
            object.__setattr__(self, name, readonly(value))
        for name, value in optional.items():
            object.__setattr__(self, name, value)

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_arrays(
        cls,
        sensor: ArrayLike,
        time: ArrayLike,
        azimuth: ArrayLike,
        elevation: ArrayLike | None = None,
        attributes: Mapping[str, ArrayLike] | None = None,
        truth: ArrayLike | None = None,
        sigma_azimuth: ArrayLike | None = None,
        sigma_elevation: ArrayLike | None = None,
        sensor_position: ArrayLike | None = None,
        *,
        angle_unit: AngleUnit = "rad",
        azimuth_convention: AzimuthConvention = "math",
        check_angle_unit: bool = True,
    ) -> MeasurementTable:
        """Build a table from column arrays (see the class docstring for each column).

        ``angle_unit`` (``"rad"`` or ``"deg"``) is the unit of the angle and noise columns,
        ``azimuth_convention`` (``"math"``: counter-clockwise from east, or ``"compass"``:
        clockwise from north) the azimuth's; the table stores radians counter-clockwise from
        east (:mod:`passive_assoc.data.angles`).

        >>> t = MeasurementTable.from_arrays([0, 1], [0.0, 0.0], [0.0, 90.0], angle_unit="deg",
        ...                                  azimuth_convention="compass")
        >>> (t.azimuth / np.pi).tolist()  # north is π/2, east is 0
        [0.5, 0.0]
        """
        check_angle_convention(angle_unit, azimuth_convention)
        attrs = dict(attributes or {})

        def angle(name: str, value: ArrayLike | None) -> Any:
            return None if value is None else from_user_angle(as_float_array(name, value), angle_unit)

        az = as_float_array("azimuth", azimuth)
        return cls(
            sensor,  # type: ignore[arg-type]
            time,  # type: ignore[arg-type]
            from_user_azimuth(az, angle_unit, azimuth_convention),
            angle("elevation", elevation),
            attrs,  # type: ignore[arg-type]
            truth,  # type: ignore[arg-type]
            angle("sigma_azimuth", sigma_azimuth),
            angle("sigma_elevation", sigma_elevation),
            sensor_position,  # type: ignore[arg-type]
            check_angle_unit=check_angle_unit,
        )

    @classmethod
    def from_columns(
        cls,
        columns: Mapping[str, ArrayLike],
        *,
        angle_unit: AngleUnit = "rad",
        azimuth_convention: AzimuthConvention = "math",
        check_angle_unit: bool = True,
        source: str = "columns",
    ) -> MeasurementTable:
        """Inverse of :meth:`to_arrays`: flat column names, attributes prefixed ``attr_``;
        the angle convention as in :meth:`from_arrays`. ``source`` names where the columns
        came from in every error (a file's name).

        Raises
        ------
        ValueError
            If a required column (sensor, time, azimuth) is missing or a column is unknown.
        """
        names = list(columns)
        for required in _CORE[:3]:
            if required not in columns:
                given = [n[len(ATTRIBUTE_PREFIX) :] if n.startswith(ATTRIBUTE_PREFIX) else n for n in names]
                raise ValueError(
                    f"{source}: missing required column {required!r} (got {given}; the names read: "
                    "docs/guide.md, 'Your own data')"
                )
        attrs: dict[str, ArrayLike] = {}
        for name in names:
            if name.startswith(ATTRIBUTE_PREFIX):
                attrs[name[len(ATTRIBUTE_PREFIX) :]] = columns[name]
            elif name not in _KNOWN:
                raise ValueError(
                    f"{source}: unknown column {name!r}; expected {list(_KNOWN)} or '{ATTRIBUTE_PREFIX}<name>'"
                )
        try:
            return cls.from_arrays(
                columns["sensor"],
                columns["time"],
                columns["azimuth"],
                columns.get("elevation"),
                attrs,
                columns.get("truth"),
                columns.get("sigma_azimuth"),
                columns.get("sigma_elevation"),
                _platform(columns, source),
                angle_unit=angle_unit,
                azimuth_convention=azimuth_convention,
                check_angle_unit=check_angle_unit,
            )
        except ValueError as err:
            if source == "columns":
                raise
            raise ValueError(f"{source}: {err}") from None

    # ------------------------------------------------------------------ queries
    def __len__(self) -> int:
        return int(self.sensor.shape[0])

    @property
    def ndim(self) -> int:
        """2 if every elevation is NaN (bearing-only, including an empty table), else 3."""
        return 2 if bool(np.isnan(self.elevation).all()) else 3

    def to_arrays(self) -> dict[str, NDArray[Any]]:
        """Writable copies of the columns: sensor, time, azimuth, elevation, [truth],
        [sigma_azimuth], [sigma_elevation], [sensor_x, sensor_y, (sensor_z in 3-D)], attr_*."""
        out: dict[str, NDArray[Any]] = {name: getattr(self, name).copy() for name in _CORE}
        if self.truth is not None:
            out["truth"] = self.truth.copy()
        for name in _NOISE:
            if getattr(self, name) is not None:
                out[name] = getattr(self, name).copy()
        if self.sensor_position is not None:
            for k, name in enumerate(_PLATFORM[: 2 if self.ndim == 2 else 3]):
                out[name] = self.sensor_position[:, k].copy()
        for name, value in self.attributes.items():
            out[ATTRIBUTE_PREFIX + name] = value.copy()
        return out

    def select(self, indices: ArrayLike) -> MeasurementTable:
        """New table of the given rows, in the given order.

        Parameters
        ----------
        indices : array_like of int, or of bool with length N
            Row indices in ``[0, N)`` (repeats allowed, negatives rejected) or a mask.
        """
        arr = np.asarray(indices)
        if arr.dtype.kind == "b":
            if arr.shape != (len(self),):
                raise ValueError(f"indices: boolean mask has shape {arr.shape}, expected ({len(self)},)")
            idx = np.flatnonzero(arr)
        else:
            idx = as_int_array("indices", arr, ndim=1)
            bad = (idx < 0) | (idx >= len(self))
            if bad.any():
                i = first(bad)
                raise ValueError(f"indices[{i}] = {idx[i]} is out of range for a table of {len(self)} rows")
        return MeasurementTable(
            self.sensor[idx],
            self.time[idx],
            self.azimuth[idx],
            self.elevation[idx],
            {k: v[idx] for k, v in self.attributes.items()},
            None if self.truth is None else self.truth[idx],
            None if self.sigma_azimuth is None else self.sigma_azimuth[idx],
            None if self.sigma_elevation is None else self.sigma_elevation[idx],
            None if self.sensor_position is None else self.sensor_position[idx],
            check_angle_unit=False,  # checked when this table was built, or waived then
        )

    def report_sigmas(self, sensors: SensorNetwork) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Each report's noise stds ``(σ_azimuth, σ_elevation)``, radians: its own where the
        table gives one, its sensor's otherwise (σ_elevation NaN in 2-D)."""
        self.validate_against(sensors)
        azimuth = sensors.sigma_azimuth[self.sensor].astype(np.float64)
        if self.sigma_azimuth is not None:
            azimuth = np.where(np.isnan(self.sigma_azimuth), azimuth, self.sigma_azimuth)
        elevation = sensors.sigma_elevation[self.sensor].astype(np.float64)
        if sensors.ndim == 3 and self.sigma_elevation is not None:
            elevation = np.where(np.isnan(self.sigma_elevation), elevation, self.sigma_elevation)
        return azimuth, elevation

    def time_order(self) -> NDArray[np.int64]:
        """Row permutation that sorts by time (stable: ties keep their current order)."""
        return np.argsort(self.time, kind="stable").astype(np.int64)

    def sorted_by_time(self) -> MeasurementTable:
        """New table sorted by time; see :meth:`time_order` for the permutation."""
        return self.select(self.time_order())

    def validate_against(self, sensors: SensorNetwork) -> None:
        """Check that this table can come from ``sensors``.

        Raises
        ------
        TypeError
            If ``sensors`` is not a :class:`SensorNetwork`.
        ValueError
            If a row names a sensor the network does not have (the first such row is
            named), or if the table's dimension differs from the network's. An empty table
            always passes.
        """
        if not isinstance(sensors, SensorNetwork):
            raise TypeError(f"sensors: expected a SensorNetwork, got {type(sensors).__name__}")
        if len(self) == 0:
            return
        bad = self.sensor >= sensors.n_sensors
        if bad.any():
            i = first(bad)
            raise ValueError(
                f"sensor[{i}] = {self.sensor[i]} (row {i}) is not a sensor of the network "
                f"(valid: 0..{sensors.n_sensors - 1})"
            )
        if self.ndim != sensors.ndim:
            elevation = "present" if self.ndim == 3 else "NaN"
            raise ValueError(
                f"measurements: the table is {self.ndim}-D (elevation {elevation}) "
                f"but the sensor network is {sensors.ndim}-D"
            )

    # ------------------------------------------------------------------ I/O
    def to_csv(self, path: str | os.PathLike[str]) -> None:
        """Write a CSV file with a header row; floats are written with ``repr`` (exact).

        Columns: sensor, time, azimuth, elevation, then truth (only if present), then one
        ``attr_<name>`` column per attribute. :meth:`from_csv` reads it back bit-exactly.
        """
        write_csv(path, self.to_arrays())

    @classmethod
    def from_csv(
        cls,
        path: str | os.PathLike[str],
        *,
        angle_unit: AngleUnit = "rad",
        azimuth_convention: AzimuthConvention = "math",
        check_angle_unit: bool = True,
        time_origin: TimeOrigin = None,
        frame: LocalFrame | None = None,
    ) -> MeasurementTable:
        r"""Read a table written by :meth:`to_csv`, or a measurement file from another tool.

        Required columns: ``sensor`` (the sensor file's id), ``time`` (s, or ISO 8601
        date-times), ``azimuth``; optional ``elevation`` (3-D), ``sigma_azimuth`` and
        ``sigma_elevation`` (per-report noise), ``truth``, ``attr_<name>``; the aliases of
        other tools (``sensor_id``, ``t``, ``timestamp``, ``bearing``, ``sigma_bearing``, …)
        are read as these. Column names may have spaces around them. Any other column is kept
        as an attribute when every cell is a number, and ignored with a warning otherwise
        (:mod:`passive_assoc.data.measurement_files`). Every error names the file.

        Parameters
        ----------
        path : str or path-like
        angle_unit : {"rad", "deg"}
            The unit of ``azimuth``, ``elevation`` and the noise columns in the file. Stored
            in radians.
        azimuth_convention : {"math", "compass"}
            ``"math"``: azimuth counter-clockwise from east (+x); ``"compass"``: bearing
            clockwise from north. Stored as ``"math"``.
        check_angle_unit : bool
            Refuse angles beyond ±2π (azimuth) or ±π/2 (elevation) radians, almost surely
            degrees: see the class.
        time_origin : str or datetime, optional
            The instant ISO 8601 times are counted from (default: the earliest of the file).
        frame : LocalFrame, optional
            The network's geodetic frame (``SensorNetwork.frame``): needed when the file gives
            a moving sensor's position as ``sensor_lat``, ``sensor_lon``, ``sensor_alt``.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "scan.csv"
        >>> _ = path.write_text("sensor, time, azimuth, snr\n0, 0.0, 90.0, 12.5\n1, 0.0, 45.0, 9.0\n")
        >>> table = MeasurementTable.from_csv(path, angle_unit="deg")
        >>> table.azimuth.round(4).tolist(), table.attributes["snr"].tolist()
        ([1.5708, 0.7854], [12.5, 9.0])
        """
        check_angle_convention(angle_unit, azimuth_convention)
        return cls.from_columns(
            _placed(read_measurement_columns(path, _READ, ATTRIBUTE_PREFIX, time_origin), frame, path),
            angle_unit=angle_unit,
            azimuth_convention=azimuth_convention,
            check_angle_unit=check_angle_unit,
            source=repr(os.fspath(path)),
        )

    def to_parquet(self, path: str | os.PathLike[str]) -> None:
        """Write a Parquet file (optional extra ``parquet``: pyarrow) with :meth:`to_csv`'s
        columns; :meth:`from_parquet` reads it back exactly."""
        write_parquet(path, self.to_arrays())

    @classmethod
    def from_parquet(
        cls,
        path: str | os.PathLike[str],
        *,
        angle_unit: AngleUnit = "rad",
        azimuth_convention: AzimuthConvention = "math",
        check_angle_unit: bool = True,
        time_origin: TimeOrigin = None,
        frame: LocalFrame | None = None,
    ) -> MeasurementTable:
        """Read a Parquet file with :meth:`from_csv`'s columns, aliases and rules (numeric
        extra columns kept as attributes, others ignored with a warning; the angle
        convention; timestamps as seconds after ``time_origin``)."""
        check_angle_convention(angle_unit, azimuth_convention)
        return cls.from_columns(
            _placed(read_measurement_parquet(path, _READ, ATTRIBUTE_PREFIX, time_origin), frame, path),
            angle_unit=angle_unit,
            azimuth_convention=azimuth_convention,
            check_angle_unit=check_angle_unit,
            source=repr(os.fspath(path)),
        )

    def to_pandas(self) -> Any:
        """Return a :class:`pandas.DataFrame` with the columns of :meth:`to_arrays`.

        Raises
        ------
        ImportError
            If pandas is not installed (it is an optional dependency).
        """
        return import_pandas().DataFrame(self.to_arrays())

    @classmethod
    def from_pandas(
        cls,
        df: Any,
        *,
        angle_unit: AngleUnit = "rad",
        azimuth_convention: AzimuthConvention = "math",
        check_angle_unit: bool = True,
    ) -> MeasurementTable:
        """Build a table from a DataFrame with the columns of :meth:`to_arrays`, in the
        declared angle convention (as :meth:`from_arrays`)."""
        if not isinstance(df, import_pandas().DataFrame):
            raise TypeError(f"df: expected a pandas.DataFrame, got {type(df).__name__}")
        return cls.from_columns(
            {str(c): df[c].to_numpy() for c in df.columns},
            angle_unit=angle_unit,
            azimuth_convention=azimuth_convention,
            check_angle_unit=check_angle_unit,
            source="df",
        )

    # ------------------------------------------------------------------ dunder
    def __eq__(self, other: object) -> bool:
        if not isinstance(other, MeasurementTable):
            return NotImplemented
        mine, theirs = self.to_arrays(), other.to_arrays()
        return mine.keys() == theirs.keys() and all(
            mine[k].dtype == theirs[k].dtype and np.array_equal(mine[k], theirs[k], equal_nan=mine[k].dtype.kind == "f")
            for k in mine
        )

    __hash__ = None  # type: ignore[assignment]  # value equality over arrays

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        # Rebuilt through the constructor: arrays a transport hands back (Dask's out-of-band
        # buffers) may be unaligned views, which the core refuses; the constructor copies.
        return (_rebuild, (self.to_arrays(),))

    def __repr__(self) -> str:
        sensors = np.unique(self.sensor).tolist()
        return (
            f"MeasurementTable(n_rows={len(self)}, ndim={self.ndim}, sensors={sensors}, "
            f"attributes={list(self.attributes)}, truth={self.truth is not None})"
        )


def _platform(columns: Mapping[str, ArrayLike], source: str) -> NDArray[np.float64] | None:
    """The ``sensor_x``, ``sensor_y`` [, ``sensor_z``] columns as ``(N, 3)`` positions."""
    given = [name for name in _PLATFORM if name in columns]
    if not given:
        return None
    if given[:2] != ["sensor_x", "sensor_y"]:
        raise ValueError(f"{source}: a moving sensor's position needs 'sensor_x' and 'sensor_y' (got {given})")
    xyz = [np.asarray(columns[name], dtype=np.float64) for name in given]
    if len(xyz) == 2:
        xyz.append(np.where(np.isnan(xyz[0]), np.nan, 0.0))
    return np.column_stack(xyz)


def _placed(
    columns: dict[str, NDArray[Any]], frame: LocalFrame | None, path: str | os.PathLike[str]
) -> dict[str, NDArray[Any]]:
    """A file's ``sensor_lat``, ``sensor_lon``, ``sensor_alt`` as ``sensor_x``, ... in ``frame``."""
    if any(name in columns for name in ("sensor_lat", "sensor_lon", "sensor_alt")) and frame is None:
        raise ValueError(
            f"frame: {os.fspath(path)!r} gives sensor positions as latitude and longitude; pass the "
            "network's frame (SensorNetwork.frame) to place them"
        )
    placed, _ = place_columns(
        columns, frame, prefix="sensor_", planar="elevation" not in columns, source=repr(os.fspath(path))
    )
    return placed


def _rebuild(columns: dict[str, NDArray[Any]]) -> MeasurementTable:
    """Unpickling: the columns as they were, the angle check done when they were built."""
    return MeasurementTable.from_columns(columns, check_angle_unit=False)
