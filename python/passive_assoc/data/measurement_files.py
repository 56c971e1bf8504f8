"""Measurement files from other tools: what :meth:`MeasurementTable.from_csv` accepts beyond
the columns it writes.

* Column names may carry surrounding spaces and the file a UTF-8 byte-order mark.
* ``sensor``, ``time`` and ``azimuth`` are required; ``elevation`` (3-D), ``truth`` and
  ``attr_<name>`` columns are optional.
* Any other column is *kept as an attribute* under its own name when every cell is a number
  (an SNR, a frequency: usable by the attribute gates), and *ignored with a warning* that
  names it otherwise (a text label).
* Header aliases that other tools write are read as the library's names (matched without
  regard to case): ``sensor_id`` → ``sensor``; ``t``, ``timestamp`` → ``time``; ``bearing``,
  ``az`` → ``azimuth``; ``el`` → ``elevation``; ``sigma_bearing``, ``sigma_az`` →
  ``sigma_azimuth``; ``sigma_el`` → ``sigma_elevation``. A file with both a name and its
  alias is refused.
* A ``time`` column of ISO 8601 date-times (``2024-05-01T12:00:00.250Z``) becomes seconds
  after ``time_origin`` (default: the earliest time of the file); give the same origin to
  every file of one run so that their times agree.
* The angle columns' unit and azimuth convention are declared by the reader's
  ``angle_unit`` and ``azimuth_convention`` (:mod:`passive_assoc.data.angles`).
* Per-report noise stds ``sigma_azimuth`` / ``sigma_elevation`` and the reporting sensor's
  position ``sensor_x``, ``sensor_y``, ``sensor_z`` (a moving platform) are optional row by
  row: an empty cell means the sensor's value.
* Every error names the file.
"""

from __future__ import annotations

import datetime as dt
import os
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._warn import warn_at_caller
from ._io import is_numeric, parse_column, read_csv_text, zip_columns
from .angles import AngleUnit

__all__ = ["AngleUnit", "TimeOrigin", "read_measurement_columns", "read_measurement_parquet", "write_parquet"]

PARQUET_HINT = "Parquet files need pyarrow: pip install 'passive-assoc[parquet]'"

#: An ISO 8601 text or a datetime: the instant ISO times are counted from.
TimeOrigin = str | dt.datetime | None
_INTEGER = ("sensor", "truth")
#: Per-report columns whose empty cells mean "the sensor's value" (NaN).
_OPTIONAL_PER_ROW = ("sigma_azimuth", "sigma_elevation", "sensor_x", "sensor_y", "sensor_z")
#: Header aliases other tools write, lower case, and the library's names for them.
ALIASES = {
    "sensor_id": "sensor",
    "t": "time",
    "timestamp": "time",
    "bearing": "azimuth",
    "az": "azimuth",
    "el": "elevation",
    "sigma_bearing": "sigma_azimuth",
    "sigma_az": "sigma_azimuth",
    "sigma_el": "sigma_elevation",
}


def canonical_name(name: str, known: tuple[str, ...]) -> str:
    """The library's name of a header: a known name or an alias, matched without regard to
    case; any other name as it is."""
    lowered = name.strip().lower()
    if lowered in known:
        return lowered
    return ALIASES.get(lowered, name.strip())


def _rename(path: str | os.PathLike[str], header: list[str], known: tuple[str, ...]) -> list[str]:
    """The header in the library's names; a ValueError naming the file if two headers mean
    one column."""
    names = [canonical_name(name, known) for name in header]
    for k, name in enumerate(names):
        if name in names[:k]:
            first = header[names.index(name)]
            raise ValueError(
                f"path: {os.fspath(path)!r} has both {first.strip()!r} and {header[k].strip()!r}, "
                f"which both mean {name!r}"
            )
    return names


def _origin(time_origin: TimeOrigin) -> dt.datetime | None:
    if time_origin is None or isinstance(time_origin, dt.datetime):
        return time_origin
    if isinstance(time_origin, str):
        try:
            return dt.datetime.fromisoformat(time_origin.strip())
        except ValueError:
            raise ValueError(f"time_origin: {time_origin!r} is not an ISO 8601 date-time") from None
    raise TypeError(f"time_origin: expected an ISO 8601 str or a datetime, got {type(time_origin).__name__}")


def parse_times(path: str | os.PathLike[str], values: list[str], time_origin: TimeOrigin) -> NDArray[np.float64]:
    """A time column as seconds: numbers as they are, ISO 8601 date-times as seconds after
    ``time_origin`` (default: the earliest of them). Mixed or unreadable cells are a
    ValueError naming the line and the file."""
    origin = _origin(time_origin)
    if is_numeric(values):
        return parse_column(path, "time", values, integer=False)
    instants = []
    for r, text in enumerate(values):
        try:
            instants.append(dt.datetime.fromisoformat(text.strip()))
        except ValueError:
            raise ValueError(
                f"time: line {r + 2} has {text!r}, neither a number of seconds nor an ISO 8601 date-time "
                f"(file {os.fspath(path)!r})"
            ) from None
    aware = {t.tzinfo is not None for t in instants}
    if origin is not None:
        aware.add(origin.tzinfo is not None)
    if len(aware) > 1:
        raise ValueError(
            f"time: some date-times have a time zone and some do not (file {os.fspath(path)!r}); "
            "give every one (and time_origin) a zone, e.g. Z"
        )
    start = origin if origin is not None else min(instants)
    return np.array([(t - start).total_seconds() for t in instants], dtype=np.float64)


def read_measurement_columns(
    path: str | os.PathLike[str], known: tuple[str, ...], prefix: str, time_origin: TimeOrigin = None
) -> dict[str, NDArray[Any]]:
    """The columns of a measurement CSV file under the library's names (aliases renamed,
    ISO times in seconds), unknown numeric ones renamed ``prefix + name`` (attributes),
    unknown text ones dropped with a warning; angles as the file has them."""
    header, rows = read_csv_text(path)
    if len(set(header)) != len(header):
        raise ValueError(f"path: {os.fspath(path)!r} repeats a column name ({header})")
    header = _rename(path, header, known)
    columns: dict[str, NDArray[Any]] = {}
    ignored = []
    for name, values in zip_columns(header, rows):
        if name == "time":
            columns[name] = parse_times(path, values, time_origin)
        elif name in _OPTIONAL_PER_ROW:  # an empty cell: the sensor's value
            columns[name] = parse_column(path, name, [v if v.strip() else "nan" for v in values], integer=False)
        elif name in known or name.startswith(prefix):
            columns[name] = parse_column(path, name, values, integer=name in _INTEGER)
        elif is_numeric(values):
            columns[prefix + name] = parse_column(path, name, values, integer=False)
        else:
            ignored.append(name)
    return _finish(path, columns, ignored)


def _finish(
    path: str | os.PathLike[str], columns: dict[str, NDArray[Any]], ignored: list[str]
) -> dict[str, NDArray[Any]]:
    """Warns of the ignored columns: the last step of both readers."""
    if ignored:
        warn_at_caller(
            f"{os.fspath(path)!r}: ignoring non-numeric column(s) {ignored}; numeric extra columns are kept as "
            "attributes"
        )
    return columns


def _pyarrow_parquet() -> Any:
    try:
        import pyarrow.parquet as pq
    except ImportError as err:
        raise ImportError(PARQUET_HINT) from err
    return pq


def read_measurement_parquet(
    path: str | os.PathLike[str], known: tuple[str, ...], prefix: str, time_origin: TimeOrigin = None
) -> dict[str, NDArray[Any]]:
    """:func:`read_measurement_columns` for a Parquet file: the same aliases and rules for
    unknown columns (numeric: attributes; other types: ignored with a warning); a time column
    of timestamps becomes seconds as ISO texts do."""
    table = _pyarrow_parquet().read_table(path)
    columns: dict[str, NDArray[Any]] = {}
    ignored = []
    for name, key in zip(table.column_names, _rename(path, list(table.column_names), known), strict=True):
        values = table.column(name).to_numpy(zero_copy_only=False)
        numeric = values.dtype.kind in "iuf"
        if key == "time" and values.dtype.kind == "M":  # timestamps: as ISO texts
            columns[key] = parse_times(path, [str(v) for v in values.astype("datetime64[us]")], time_origin)
            continue
        if key in known or key.startswith(prefix):
            if not numeric:
                raise ValueError(
                    f"{key}: column of type {table.column(name).type} is not numeric (file {os.fspath(path)!r})"
                )
            columns[key] = values
        elif numeric:
            columns[prefix + key] = values.astype(np.float64)
        else:
            ignored.append(key)
    return _finish(path, columns, ignored)


def write_parquet(path: str | os.PathLike[str], columns: dict[str, NDArray[Any]]) -> None:
    """Write named columns as a Parquet file."""
    import pyarrow as pa

    _pyarrow_parquet().write_table(pa.table({k: np.asarray(v) for k, v in columns.items()}), path)
