"""Measurement files from other tools: what :meth:`MeasurementTable.from_csv` accepts beyond
the columns it writes.

* Column names may carry surrounding spaces and the file a UTF-8 byte-order mark.
* ``sensor``, ``time`` and ``azimuth`` are required; ``elevation`` (3-D), ``truth`` and
  ``attr_<name>`` columns are optional.
* Any other column is *kept as an attribute* under its own name when every cell is a number
  (an SNR, a frequency: usable by the attribute gates), and *ignored with a warning* that
  names it otherwise (a text label).
* ``angle_unit="deg"`` reads ``azimuth`` and ``elevation`` in degrees (azimuth
  counter-clockwise from +x, elevation up from the horizontal plane — METHODS §0; not a
  compass bearing).
"""

from __future__ import annotations

import os
import warnings
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from ._io import is_numeric, parse_column, read_csv_text, zip_columns

__all__ = ["AngleUnit", "read_measurement_columns", "read_measurement_parquet", "write_parquet"]

PARQUET_HINT = "Parquet files need pyarrow: pip install 'passive-assoc[parquet]'"

AngleUnit = Literal["rad", "deg"]
_INTEGER = ("sensor", "truth")
_ANGLES = ("azimuth", "elevation")


def read_measurement_columns(
    path: str | os.PathLike[str], known: tuple[str, ...], prefix: str, angle_unit: AngleUnit
) -> dict[str, NDArray[Any]]:
    """The columns of a measurement CSV file, unknown numeric ones renamed ``prefix + name``
    (attributes), unknown text ones dropped with a warning, angles in radians."""
    if angle_unit not in ("rad", "deg"):
        raise ValueError(f"angle_unit: must be 'rad' or 'deg', got {angle_unit!r}")
    header, rows = read_csv_text(path)
    if len(set(header)) != len(header):
        raise ValueError(f"path: {os.fspath(path)!r} repeats a column name ({header})")
    columns: dict[str, NDArray[Any]] = {}
    ignored = []
    for name, values in zip_columns(header, rows):
        if name in known or name.startswith(prefix):
            columns[name] = parse_column(path, name, values, integer=name in _INTEGER)
        elif is_numeric(values):
            columns[prefix + name] = parse_column(path, name, values, integer=False)
        else:
            ignored.append(name)
    return _finish(path, columns, ignored, angle_unit)


def _finish(
    path: str | os.PathLike[str], columns: dict[str, NDArray[Any]], ignored: list[str], angle_unit: AngleUnit
) -> dict[str, NDArray[Any]]:
    """Warns of the ignored columns and converts degrees: the last steps of both readers."""
    if ignored:
        warnings.warn(
            f"{os.fspath(path)!r}: ignoring non-numeric column(s) {ignored}; numeric extra columns are kept as "
            "attributes",
            UserWarning,
            stacklevel=4,
        )
    if angle_unit == "deg":
        for name in _ANGLES:
            if name in columns:
                columns[name] = np.radians(columns[name])
    return columns


def _pyarrow_parquet() -> Any:
    try:
        import pyarrow.parquet as pq
    except ImportError as err:
        raise ImportError(PARQUET_HINT) from err
    return pq


def read_measurement_parquet(
    path: str | os.PathLike[str], known: tuple[str, ...], prefix: str, angle_unit: AngleUnit
) -> dict[str, NDArray[Any]]:
    """:func:`read_measurement_columns` for a Parquet file: the same rules for unknown columns
    (numeric: attributes; other types: ignored with a warning) and for ``angle_unit``."""
    if angle_unit not in ("rad", "deg"):
        raise ValueError(f"angle_unit: must be 'rad' or 'deg', got {angle_unit!r}")
    table = _pyarrow_parquet().read_table(path)
    columns: dict[str, NDArray[Any]] = {}
    ignored = []
    for name in table.column_names:
        values = table.column(name).to_numpy(zero_copy_only=False)
        numeric = values.dtype.kind in "iuf"
        key = name.strip()
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
    return _finish(path, columns, ignored, angle_unit)


def write_parquet(path: str | os.PathLike[str], columns: dict[str, NDArray[Any]]) -> None:
    """Write named columns as a Parquet file."""
    import pyarrow as pa

    _pyarrow_parquet().write_table(pa.table({k: np.asarray(v) for k, v in columns.items()}), path)
