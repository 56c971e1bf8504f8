"""Columnar table of angle measurements (METHODS §0).

One row per reported line of sight: ``sensor`` index, ``time`` (s), ``azimuth`` (rad),
``elevation`` (rad, NaN for a 2-D bearing-only sensor), optional emitter ``attributes``
(METHODS §3), and, for simulated data only, a hidden ``truth`` label (target index, or -1
for clutter) that no algorithm may read.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import as_float_array, as_int_array, readonly, require_finite
from ._io import import_pandas, write_csv
from .measurement_files import AngleUnit, read_measurement_columns, read_measurement_parquet, write_parquet
from .sensors import SensorNetwork

__all__ = ["MeasurementTable", "ATTRIBUTE_PREFIX"]

#: Column-name prefix for attributes in CSV files, DataFrames and :meth:`to_arrays`.
ATTRIBUTE_PREFIX = "attr_"
_CORE = ("sensor", "time", "azimuth", "elevation")


def _first(mask: NDArray[np.bool_]) -> int:
    return int(np.flatnonzero(mask)[0])


def _check_attribute_name(name: Any) -> str:
    """Attribute names become CSV headers, so keep them plain identifiers-ish."""
    if not isinstance(name, str):
        raise TypeError(f"attributes: names must be str, got {name!r}")
    if not name or any(c in name for c in ',"\r\n'):
        raise ValueError(f'attributes: invalid name {name!r} (empty, or has , " or newline)')
    return name


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

    def __post_init__(self) -> None:
        sensor = as_int_array("sensor", self.sensor, ndim=1)
        n = sensor.shape[0]
        if (sensor < 0).any():
            i = _first(sensor < 0)
            raise ValueError(f"sensor[{i}] = {sensor[i]}; sensor indices must be >= 0")
        columns = {
            "sensor": sensor,
            "time": self._column("time", self.time, n),
            "azimuth": self._column("azimuth", self.azimuth, n),
            "elevation": self._elevation(n),
        }
        attrs = self._attributes(n)
        truth = self._truth(n)
        _warn_if_degrees(columns["azimuth"], columns["elevation"])
        for name, value in columns.items():
            object.__setattr__(self, name, readonly(value))
        object.__setattr__(self, "attributes", MappingProxyType(attrs))
        object.__setattr__(self, "truth", None if truth is None else readonly(truth))

    def _elevation(self, n: int) -> NDArray[np.float64]:
        """All finite (3-D) or all NaN (2-D); a mixture is almost surely a data error."""
        if self.elevation is None:
            return np.full(n, np.nan)
        elevation = self._column("elevation", self.elevation, n, finite=False)
        nan = np.isnan(elevation)
        if nan.any() and not nan.all():
            # Point at the odd one out relative to the first row's kind.
            i = _first(~nan) if nan[0] else _first(nan)
            raise ValueError(
                f"elevation[{i}] = {elevation[i].item()!r}; elevation must be all finite (3-D) or all NaN (2-D)"
            )
        if np.isinf(elevation).any():
            i = _first(np.isinf(elevation))
            raise ValueError(f"elevation[{i}] = {elevation[i].item()!r}; must be finite or NaN")
        return elevation

    def _truth(self, n: int) -> NDArray[np.int64] | None:
        if self.truth is None:
            return None
        truth = as_int_array("truth", self.truth, ndim=1)
        self._check_length("truth", truth, n)
        if (truth < -1).any():
            i = _first(truth < -1)
            raise ValueError(f"truth[{i}] = {truth[i]}; labels are target indices >= 0 or -1 (clutter)")
        return truth

    @staticmethod
    def _check_length(name: str, arr: NDArray[Any], n: int) -> None:
        if arr.shape[0] != n:
            raise ValueError(
                f"{name}: has length {arr.shape[0]} but sensor has length {n}; all columns must have the same length"
            )

    @classmethod
    def _column(cls, name: str, value: ArrayLike, n: int, finite: bool = True) -> NDArray[np.float64]:
        arr = as_float_array(name, value, ndim=1)
        cls._check_length(name, arr, n)
        if finite:
            require_finite(name, arr)
        return arr

    def _attributes(self, n: int) -> dict[str, NDArray[np.float64]]:
        if not isinstance(self.attributes, Mapping):
            raise TypeError(f"attributes: expected a mapping name -> array, got {type(self.attributes).__name__}")
        out = {}
        for key, value in self.attributes.items():
            name = _check_attribute_name(key)
            out[name] = readonly(self._column(f"attributes[{name!r}]", value, n))
        return out

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
    ) -> MeasurementTable:
        """Build a table from column arrays (see the class docstring for each column)."""
        attrs = dict(attributes or {})
        return cls(sensor, time, azimuth, elevation, attrs, truth)  # type: ignore[arg-type]

    @classmethod
    def from_columns(cls, columns: Mapping[str, ArrayLike]) -> MeasurementTable:
        """Inverse of :meth:`to_arrays`: flat column names, attributes prefixed ``attr_``.

        Raises
        ------
        ValueError
            If a required column (sensor, time, azimuth) is missing or a column is unknown.
        """
        names = list(columns)
        for required in _CORE[:3]:
            if required not in columns:
                raise ValueError(f"columns: missing required column {required!r} (got {names})")
        attrs: dict[str, ArrayLike] = {}
        for name in names:
            if name.startswith(ATTRIBUTE_PREFIX):
                attrs[name[len(ATTRIBUTE_PREFIX) :]] = columns[name]
            elif name not in _CORE and name != "truth":
                raise ValueError(
                    f"columns: unknown column {name!r}; expected {list(_CORE)}, 'truth' or '{ATTRIBUTE_PREFIX}<name>'"
                )
        return cls.from_arrays(
            columns["sensor"],
            columns["time"],
            columns["azimuth"],
            columns.get("elevation"),
            attrs,
            columns.get("truth"),
        )

    # ------------------------------------------------------------------ queries
    def __len__(self) -> int:
        return int(self.sensor.shape[0])

    @property
    def ndim(self) -> int:
        """2 if every elevation is NaN (bearing-only, including an empty table), else 3."""
        return 2 if bool(np.isnan(self.elevation).all()) else 3

    def to_arrays(self) -> dict[str, NDArray[Any]]:
        """Writable copies of the columns: sensor, time, azimuth, elevation, [truth], attr_*."""
        out: dict[str, NDArray[Any]] = {name: getattr(self, name).copy() for name in _CORE}
        if self.truth is not None:
            out["truth"] = self.truth.copy()
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
                i = _first(bad)
                raise ValueError(f"indices[{i}] = {idx[i]} is out of range for a table of {len(self)} rows")
        return MeasurementTable(
            self.sensor[idx],
            self.time[idx],
            self.azimuth[idx],
            self.elevation[idx],
            {k: v[idx] for k, v in self.attributes.items()},
            None if self.truth is None else self.truth[idx],
        )

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
            i = _first(bad)
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
    def from_csv(cls, path: str | os.PathLike[str], *, angle_unit: AngleUnit = "rad") -> MeasurementTable:
        r"""Read a table written by :meth:`to_csv`, or a measurement file from another tool.

        Required columns: ``sensor`` (the sensor file's id), ``time`` (s), ``azimuth``;
        optional ``elevation`` (3-D), ``truth``, ``attr_<name>``. Column names may have spaces
        around them. Any other column is kept as an attribute when every cell is a number, and
        ignored with a warning otherwise (:mod:`passive_assoc.data.measurement_files`).

        Parameters
        ----------
        path : str or path-like
        angle_unit : {"rad", "deg"}
            The unit of ``azimuth`` and ``elevation`` in the file (azimuth counter-clockwise
            from +x, elevation up; not a compass bearing). Stored in radians.

        Examples
        --------
        >>> import tempfile, pathlib
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "scan.csv"
        >>> _ = path.write_text("sensor, time, azimuth, snr\n0, 0.0, 90.0, 12.5\n1, 0.0, 45.0, 9.0\n")
        >>> table = MeasurementTable.from_csv(path, angle_unit="deg")
        >>> table.azimuth.round(4).tolist(), table.attributes["snr"].tolist()
        ([1.5708, 0.7854], [12.5, 9.0])
        """
        return cls.from_columns(read_measurement_columns(path, (*_CORE, "truth"), ATTRIBUTE_PREFIX, angle_unit))

    def to_parquet(self, path: str | os.PathLike[str]) -> None:
        """Write a Parquet file (optional extra ``parquet``: pyarrow) with :meth:`to_csv`'s
        columns; :meth:`from_parquet` reads it back exactly."""
        write_parquet(path, self.to_arrays())

    @classmethod
    def from_parquet(cls, path: str | os.PathLike[str], *, angle_unit: AngleUnit = "rad") -> MeasurementTable:
        """Read a Parquet file with :meth:`from_csv`'s columns and rules (numeric extra
        columns kept as attributes, others ignored with a warning; ``angle_unit``)."""
        return cls.from_columns(read_measurement_parquet(path, (*_CORE, "truth"), ATTRIBUTE_PREFIX, angle_unit))

    def to_pandas(self) -> Any:
        """Return a :class:`pandas.DataFrame` with the columns of :meth:`to_arrays`.

        Raises
        ------
        ImportError
            If pandas is not installed (it is an optional dependency).
        """
        return import_pandas().DataFrame(self.to_arrays())

    @classmethod
    def from_pandas(cls, df: Any) -> MeasurementTable:
        """Build a table from a DataFrame with the columns of :meth:`to_arrays`."""
        if not isinstance(df, import_pandas().DataFrame):
            raise TypeError(f"df: expected a pandas.DataFrame, got {type(df).__name__}")
        return cls.from_columns({str(c): df[c].to_numpy() for c in df.columns})

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
        return (MeasurementTable.from_columns, (self.to_arrays(),))

    def __repr__(self) -> str:
        sensors = np.unique(self.sensor).tolist()
        return (
            f"MeasurementTable(n_rows={len(self)}, ndim={self.ndim}, sensors={sensors}, "
            f"attributes={list(self.attributes)}, truth={self.truth is not None})"
        )


def _warn_if_degrees(azimuth: NDArray[Any], elevation: NDArray[Any]) -> None:
    """Angles beyond ±2π (azimuth) or ±π/2 (elevation) are almost surely degrees given as
    radians, which silently gives no tracks: say so (a warning: the arithmetic still works)."""
    for name, values, limit, text in (
        ("azimuth", azimuth, 2 * np.pi, "±2π"),
        ("elevation", elevation, np.pi / 2, "±π/2"),
    ):
        outside = np.abs(values) > limit * (1 + 1e-12)  # NaN (2-D elevation) compares False
        if outside.any():
            i = _first(outside)
            warnings.warn(
                f"{name}[{i}] = {float(values[i])!r} rad is beyond {text}: were the angles given in degrees? "
                "(angle_unit='deg' in MeasurementTable.from_csv, or np.radians)",
                UserWarning,
                stacklevel=4,
            )
            return
