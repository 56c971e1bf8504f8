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
:func:`network_columns` writes the radian form, which reads back exactly.
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Mapping
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ._io import parse_column, read_csv_text, write_csv, zip_columns
from .sensors import SensorNetwork

__all__ = ["network_columns", "network_from_columns", "read_sensor_csv", "write_sensor_csv"]

_KNOWN = {"sensor", "x", "y", "z", "sigma_azimuth", "sigma_elevation", "sigma_azimuth_deg", "sigma_elevation_deg"}


def read_sensor_csv(path: str | os.PathLike[str]) -> SensorNetwork:
    """A :class:`SensorNetwork` from a CSV file in the format above.

    Raises
    ------
    ValueError
        Missing or duplicated columns, a cell that is not a number, ids that are not 0 … S − 1,
        or any check of :class:`SensorNetwork` — naming the file and, where there is one, the
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
    return network_from_columns(columns, source=repr(os.fspath(path)), ignored=extra)


def network_from_columns(
    columns: Mapping[str, Any], *, source: str = "columns", ignored: list[str] | None = None
) -> SensorNetwork:
    """A :class:`SensorNetwork` from named columns (the CSV format above); ``source`` names
    where they came from in errors. Unknown column names are ignored with a warning."""
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
        return SensorNetwork(positions, sigma_az[order], ndim=2)
    return SensorNetwork(positions, sigma_az[order], sigma_el[order], ndim=3)


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


def network_columns(network: SensorNetwork) -> dict[str, NDArray[Any]]:
    """The network as named columns in radians: sensor, x, y, [z, sigma_elevation], sigma_azimuth."""
    out: dict[str, NDArray[Any]] = {
        "sensor": np.arange(network.n_sensors, dtype=np.int64),
        "x": network.positions[:, 0].copy(),
        "y": network.positions[:, 1].copy(),
    }
    if network.ndim == 3:
        out["z"] = network.positions[:, 2].copy()
    out["sigma_azimuth"] = network.sigma_azimuth.copy()
    if network.ndim == 3:
        out["sigma_elevation"] = network.sigma_elevation.copy()
    return out


def write_sensor_csv(network: SensorNetwork, path: str | os.PathLike[str]) -> None:
    """Write the network as a CSV file that :func:`read_sensor_csv` reads back exactly."""
    write_csv(path, network_columns(network))
