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

The aliases other tools write are read as these names (without regard to case):
``sensor_id`` → ``sensor``; ``sigma_bearing``, ``sigma_az`` → ``sigma_azimuth``;
``sigma_el`` → ``sigma_elevation`` (each also with ``_deg``). Every error names the file.

In place of ``x``, ``y``, ``z`` a file may give ``lat``, ``lon`` (degrees, WGS-84) and
``alt`` (metres; aliases ``latitude``, ``longitude``, ``altitude``): the sensors are then
placed in a local East-North-Up frame (:class:`~passive_assoc.data.geodetic.LocalFrame`),
given by the reader's ``frame`` or chosen around the sensors, and the network keeps it as its
``frame``. A 2-D network's sensors stay on the frame's tangent plane (z = 0).

The network is 3-D when it has an elevation std column, else 2-D (then ``z`` must be absent
or all zero). Other columns (a name, a site code) are ignored with a warning that lists them.
:meth:`SensorNetwork.to_columns` gives the radian form, which reads back exactly.

This module works on columns only; :class:`~passive_assoc.data.SensorNetwork` builds itself
from what :func:`network_arguments` returns.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._warn import warn_at_caller
from ._io import parse_column, read_csv_text, write_csv, zip_columns
from .geodetic import LocalFrame, place_columns

__all__ = ["NetworkArguments", "network_arguments", "read_sensor_columns", "write_sensor_columns"]

#: What a sensor file gives the network's constructor: positions (S, 3), azimuth stds,
#: elevation stds (None in 2-D), the dimension and the geodetic frame (None: not geodetic).
NetworkArguments = tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64] | None, int, LocalFrame | None]

_GEODETIC = ("lat", "lon", "alt")
_KNOWN = {
    "sensor",
    "x",
    "y",
    "z",
    *_GEODETIC,
    "sigma_azimuth",
    "sigma_elevation",
    "sigma_azimuth_deg",
    "sigma_elevation_deg",
}
#: Header aliases (lower case) and the names they stand for.
ALIASES = {"sensor_id": "sensor", "latitude": "lat", "longitude": "lon", "altitude": "alt"} | {
    f"{alias}{unit}": f"{name}{unit}"
    for alias, name in (
        ("sigma_bearing", "sigma_azimuth"),
        ("sigma_az", "sigma_azimuth"),
        ("sigma_el", "sigma_elevation"),
    )
    for unit in ("", "_deg")
}


def _canonical(name: str) -> str:
    lowered = name.strip().lower()
    return lowered if lowered in _KNOWN else ALIASES.get(lowered, name)


def _renamed(columns: Mapping[str, Any], source: str) -> dict[str, Any]:
    """The columns under the library's names; a ValueError when two mean one."""
    out: dict[str, Any] = {}
    for name, values in columns.items():
        key = _canonical(name)
        if key in out:
            raise ValueError(f"{source}: two columns mean {key!r} ({list(columns)})")
        out[key] = values
    return out


def read_sensor_columns(path: str | os.PathLike[str], frame: LocalFrame | None = None) -> NetworkArguments:
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
    text = _renamed(text, f"path: {os.fspath(path)!r}")
    header = list(text)
    columns = {
        name: parse_column(path, name, values, integer=name == "sensor")
        for name, values in text.items()
        if name in _KNOWN
    }
    extra = [name for name in header if name not in _KNOWN]
    return network_arguments(columns, source=repr(os.fspath(path)), ignored=extra, frame=frame)


def network_arguments(
    columns: Mapping[str, Any],
    *,
    source: str = "columns",
    ignored: list[str] | None = None,
    frame: LocalFrame | None = None,
) -> NetworkArguments:
    """The network's constructor arguments from named columns (the CSV format above);
    ``source`` names where they came from in errors. Unknown column names are ignored with a
    warning. Geodetic columns go through ``frame``, or one chosen around the sensors."""
    columns = _renamed(columns, source)
    extra = list(ignored or []) + [name for name in columns if name not in _KNOWN]
    if extra:
        warn_at_caller(f"{source}: ignoring column(s) {extra} (not part of a sensor file)")
    sigma_el = _angle_column(columns, "sigma_elevation", source)
    geodetic = any(name in columns for name in _GEODETIC)
    if not geodetic and frame is not None:
        raise ValueError(f"frame: given, but {source} has no 'lat', 'lon' columns to place with it")
    columns, frame = place_columns(columns, frame, prefix="", planar=sigma_el is None, source=source)
    for required in ("x", "y"):
        if required not in columns:
            raise ValueError(f"{source}: missing column {required!r} (got {sorted(columns)})")
    sigma_az = _angle_column(columns, "sigma_azimuth", source)
    if sigma_az is None:
        raise ValueError(f"{source}: missing column 'sigma_azimuth' (radians) or 'sigma_azimuth_deg'")
    n = len(np.asarray(columns["x"]))
    order = _order(columns, n, source)
    x, y = (np.asarray(columns[c], dtype=np.float64)[order] for c in ("x", "y"))
    z = np.asarray(columns["z"], dtype=np.float64)[order] if "z" in columns else np.zeros(n)
    positions = np.column_stack([x, y, z])
    if sigma_el is None:
        if np.any(z != 0):
            raise ValueError(
                f"{source}: sensors have heights (column 'z') but no elevation std column; a 3-D network "
                "needs 'sigma_elevation' or 'sigma_elevation_deg', a 2-D one no 'z'"
            )
        return positions, sigma_az[order], None, 2, frame
    return positions, sigma_az[order], sigma_el[order], 3, frame


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
