"""Sensor networks in and out of CSV files and pandas DataFrames.

One row per sensor:

========================  ==================================================================
column                    meaning
========================  ==================================================================
``sensor``                optional: the sensor's id, 0 … S − 1 in any order (default: the row
                          order). Measurement files name sensors by this id.
``x``, ``y``              position, metres (x east, y north)
``z``                     optional: height, metres; absent in a 2-D (bearing-only) network
``sigma_azimuth``         azimuth noise standard deviation, radians; or ``sigma_azimuth_deg``
                          in degrees
``sigma_elevation``       3-D only: elevation noise standard deviation, radians; or
                          ``sigma_elevation_deg`` in degrees
========================  ==================================================================

The network is 3-D when it has an elevation std column, else 2-D (then ``z`` must be absent
or all zero). Other columns (a name, a site code) are ignored with a warning that lists them.
:meth:`SensorNetwork.to_columns` gives the radian form, which reads back exactly.

This module works on columns only; :class:`~passive_assoc.data.SensorNetwork` builds itself
from what :func:`network_arguments` returns.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._io import parse_column, read_csv_text, write_csv, zip_columns

__all__ = ["NetworkArguments", "network_arguments", "read_sensor_columns", "write_sensor_columns"]

#: What a sensor file gives the network's constructor: positions (S, 3), azimuth stds,
#: elevation stds (None in 2-D) and the dimension.
NetworkArguments = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64] | None, int]

_KNOWN = {"sensor", "x", "y", "z", "sigma_azimuth", "sigma_elevation", "sigma_azimuth_deg", "sigma_elevation_deg"}


def read_sensor_columns(path: str | os.PathLike[str]) -> NetworkArguments:
    """The network's constructor arguments from a CSV file in the format above.

    Raises
    ------
    ValueError
        Missing or duplicated columns, a cell that is not a number, ids that are not 0 … S − 1,
        — naming the file and, where there is one, the
        column and line.
    """
    header, rows = read_csv_text(path)
    if not rows:
        raise ValueError(f"path: {os.fspath(path)!r} has a header but no sensor rows")
    text = dict(zip_columns(header, rows))
    if len(text) != len(header):
        raise ValueError(f"path: {os.fspath(path)!r} repeats a column name ({header})")
    columns = {
        name: parse_column(path, name, values, integer=name == "sensor")
        for name, values in text.items()
        if name in _KNOWN
    }
    extra = [name for name in header if name not in _KNOWN]
    return network_arguments(columns, source=repr(os.fspath(path)), ignored=extra)


def network_arguments(
    columns: Mapping[str, Any], *, source: str = "columns", ignored: list[str] | None = None
) -> NetworkArguments:
    """The network's constructor arguments from named columns (the CSV format above);
    ``source`` names where they came from in errors. Unknown column names are ignored with a
    warning."""
    extra = list(ignored or []) + [name for name in columns if name not in _KNOWN]
    if extra:
        warnings.warn(f"{source}: ignoring column(s) {extra} (not part of a sensor file)", UserWarning, stacklevel=3)
    for required in ("x", "y"):
        if required not in columns:
            raise ValueError(f"{source}: missing column {required!r} (got {sorted(columns)})")
    n = len(np.asarray(columns["x"]))
    order = _order(columns, n, source)
    x, y = (np.asarray(columns[c], dtype=np.float64)[order] for c in ("x", "y"))
    z = np.asarray(columns["z"], dtype=np.float64)[order] if "z" in columns else np.zeros(n)
    sigma_az = _angle_column(columns, "sigma_azimuth", source)
    if sigma_az is None:
        raise ValueError(f"{source}: missing column 'sigma_azimuth' (radians) or 'sigma_azimuth_deg'")
    sigma_el = _angle_column(columns, "sigma_elevation", source)
    positions = np.column_stack([x, y, z])
    if sigma_el is None:
        if np.any(z != 0):
            raise ValueError(
                f"{source}: sensors have heights (column 'z') but no elevation std column; a 3-D network "
                "needs 'sigma_elevation' or 'sigma_elevation_deg', a 2-D one no 'z'"
            )
        return positions, sigma_az[order], None, 2
    return positions, sigma_az[order], sigma_el[order], 3


def _order(columns: Mapping[str, Any], n: int, source: str) -> NDArray[np.intp]:
    """Rows in sensor-id order (the row order without a ``sensor`` column)."""
    if "sensor" not in columns:
        return np.arange(n)
    ids = np.asarray(columns["sensor"])
    if ids.dtype.kind not in "iu" or sorted(ids.tolist()) != list(range(n)):
        raise ValueError(f"{source}: column 'sensor' must hold the ids 0 … {n - 1}, each once; got {ids.tolist()}")
    return np.argsort(ids).astype(np.intp)


def _angle_column(columns: Mapping[str, Any], name: str, source: str) -> NDArray[np.float64] | None:
    """``name`` in radians, from ``name`` or ``name_deg`` (not both)."""
    if name in columns and f"{name}_deg" in columns:
        raise ValueError(f"{source}: give {name!r} (radians) or {name + '_deg'!r} (degrees), not both")
    if name in columns:
        return np.asarray(columns[name], dtype=np.float64)
    if f"{name}_deg" in columns:
        return np.radians(np.asarray(columns[f"{name}_deg"], dtype=np.float64))
    return None


def write_sensor_columns(columns: Mapping[str, NDArray[Any]], path: str | os.PathLike[str]) -> None:
    """Write a network's columns (:meth:`SensorNetwork.to_columns`) as a CSV file that
    :func:`read_sensor_columns` reads back exactly."""
    write_csv(path, columns)
