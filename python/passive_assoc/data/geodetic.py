"""Geodetic positions: WGS-84 latitude, longitude (degrees) and altitude (metres above the
ellipsoid), through a local East-North-Up frame.

The methods work in one Cartesian frame, x east, y north, z up (METHODS §0). A
:class:`LocalFrame` is that frame's origin on the ellipsoid: :meth:`~LocalFrame.to_enu` takes
geodetic positions into it and :meth:`~LocalFrame.to_geodetic` takes positions (a result's
targets, a track's states) back. The conversions are pymap3d's (``geodetic2enu``,
``enu2geodetic``: the optional extra ``geodetic``, which Stone Soup also installs). A sensor
file with ``lat``, ``lon`` [, ``alt``] columns is read through a frame that is given, or
chosen around its sensors (:meth:`LocalFrame.around`); a 2-D (bearing-only) network keeps its
sensors on the frame's tangent plane (z = 0), which is accurate while the scene spans some
tens of kilometres.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import as_float_array, require_finite

__all__ = ["GEODETIC_HINT", "LocalFrame", "place_columns"]

GEODETIC_HINT = "geodetic positions need pymap3d: pip install 'passive-assoc[geodetic]'"


def _pymap3d() -> Any:
    try:
        import pymap3d
    except ImportError as err:
        raise ImportError(GEODETIC_HINT) from err
    return pymap3d


@dataclass(frozen=True)
class LocalFrame:
    """A local East-North-Up frame: its origin's latitude and longitude (degrees, WGS-84) and
    altitude (metres above the ellipsoid).

    >>> frame = LocalFrame(54.0, 10.0)
    >>> east = frame.to_enu([54.0], [10.01], [0.0])
    >>> round(float(east[0, 0]))  # 0.01° of longitude at 54° N
    656
    >>> (frame.to_geodetic(east).round(6) + 0.0).tolist()
    [[54.0, 10.01, 0.0]]
    """

    latitude: float
    longitude: float
    altitude: float = 0.0

    def __post_init__(self) -> None:
        for name, low, high in (("latitude", -90.0, 90.0), ("longitude", -180.0, 360.0), ("altitude", None, None)):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.floating, np.integer)):
                raise TypeError(f"{name}: expected a number, got {value!r}")
            if not math.isfinite(value) or (low is not None and not low <= value <= high):  # type: ignore[operator]
                bounds = "" if low is None else f" in [{low:g}, {high:g}]"
                raise ValueError(f"{name}: must be finite{bounds}, got {value!r}")
            object.__setattr__(self, name, float(value))

    @classmethod
    def around(cls, latitude: ArrayLike, longitude: ArrayLike, altitude: ArrayLike | None = None) -> LocalFrame:
        """The frame centred on some points: their mean latitude, their circular mean
        longitude, and their mean altitude (0 without one)."""
        lat = as_float_array("latitude", latitude, ndim=1)
        lon = as_float_array("longitude", longitude, ndim=1)
        if not len(lat) or len(lat) != len(lon):
            raise ValueError(f"latitude, longitude: expected equal non-zero lengths, got {len(lat)} and {len(lon)}")
        require_finite("latitude", lat)
        require_finite("longitude", lon)
        alt = 0.0 if altitude is None else float(np.mean(as_float_array("altitude", altitude, ndim=1)))
        lon_rad = np.radians(lon)
        centre = math.degrees(math.atan2(float(np.sin(lon_rad).mean()), float(np.cos(lon_rad).mean())))
        return cls(float(lat.mean()), centre, alt)

    def to_enu(
        self, latitude: ArrayLike, longitude: ArrayLike, altitude: ArrayLike | None = None
    ) -> NDArray[np.float64]:
        """Positions ``(N, 3)`` east, north, up in metres of points given in degrees and metres
        (altitude 0 where none is given)."""
        lat = as_float_array("latitude", latitude, ndim=1)
        lon = as_float_array("longitude", longitude, ndim=1)
        alt = np.zeros(len(lat)) if altitude is None else as_float_array("altitude", altitude, ndim=1)
        if not len(lat) == len(lon) == len(alt):
            raise ValueError(f"latitude, longitude, altitude: lengths {len(lat)}, {len(lon)}, {len(alt)} differ")
        for name, values in (("latitude", lat), ("longitude", lon), ("altitude", alt)):
            require_finite(name, values)
        if (np.abs(lat) > 90.0).any():
            k = int(np.flatnonzero(np.abs(lat) > 90.0)[0])
            raise ValueError(f"latitude[{k}] = {float(lat[k])!r}; must lie in [-90, 90] degrees")
        e, n, u = _pymap3d().geodetic2enu(lat, lon, alt, self.latitude, self.longitude, self.altitude)
        return np.column_stack([e, n, u]).astype(np.float64)

    def to_geodetic(self, positions: ArrayLike) -> NDArray[np.float64]:
        """Latitude, longitude (degrees) and altitude (metres) ``(N, 3)`` of positions
        ``(N, 2)`` or ``(N, 3)`` in this frame (z = 0 for 2-D positions: on the tangent
        plane)."""
        arr = as_float_array("positions", positions, ndim=2)
        if arr.shape[1] == 2:
            arr = np.column_stack([arr, np.zeros(len(arr))])
        if arr.shape[1] != 3:
            raise ValueError(f"positions: expected shape (N, 2) or (N, 3), got {arr.shape}")
        lat, lon, alt = _pymap3d().enu2geodetic(
            arr[:, 0], arr[:, 1], arr[:, 2], self.latitude, self.longitude, self.altitude
        )
        return np.column_stack([lat, lon, alt]).astype(np.float64)


def place_columns(
    columns: Mapping[str, Any], frame: LocalFrame | None, *, prefix: str, planar: bool, source: str
) -> tuple[dict[str, Any], LocalFrame | None]:
    """``columns`` with ``{prefix}lat``, ``{prefix}lon`` [, ``{prefix}alt``] replaced by
    ``{prefix}x``, ``{prefix}y`` [, ``{prefix}z``] in ``frame`` (chosen around the points when
    None), and that frame; unchanged, with ``frame``, when there are no geodetic columns. A
    NaN latitude (an empty cell) stays NaN; z is 0 where ``planar``."""
    lat_name, lon_name, alt_name = (prefix + c for c in ("lat", "lon", "alt"))
    if not any(name in columns for name in (lat_name, lon_name, alt_name)):
        return dict(columns), frame
    if any(prefix + c in columns for c in ("x", "y", "z")):
        raise ValueError(f"{source}: give positions as {prefix}x, {prefix}y or as {lat_name}, {lon_name}, not both")
    if lat_name not in columns or lon_name not in columns:
        raise ValueError(
            f"{source}: geodetic positions need both {lat_name!r} and {lon_name!r} (got {sorted(columns)})"
        )
    lat, lon = (np.asarray(columns[c], dtype=np.float64) for c in (lat_name, lon_name))
    alt = np.asarray(columns[alt_name], dtype=np.float64) if alt_name in columns else np.zeros(len(lat))
    given = ~np.isnan(lat)
    if frame is None:
        frame = LocalFrame.around(lat[given], lon[given], alt[given])
    elif not isinstance(frame, LocalFrame):
        raise TypeError(f"frame: expected a LocalFrame, got {type(frame).__name__}")
    enu = np.full((len(lat), 3), np.nan)
    enu[given] = frame.to_enu(lat[given], lon[given], alt[given])
    out = {k: v for k, v in columns.items() if k not in (lat_name, lon_name, alt_name)}
    out[prefix + "x"], out[prefix + "y"] = enu[:, 0], enu[:, 1]
    if not planar:
        out[prefix + "z"] = enu[:, 2]
    return out, frame
