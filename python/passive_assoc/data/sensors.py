"""Passive sensor networks: where the sensors are and how noisy their angles are.

Conventions (METHODS §0): x east, y north, z up, metres; angles in radians. A 2-D
(bearing-only) network is stored with the same ``(S, 3)`` position array as a 3-D one, with
``z = 0``, so that geometry code has a single layout to handle.
"""

from __future__ import annotations

import math
import os
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.spatial import cKDTree

from .._validation import (
    as_float_array,
    as_int_array,
    readonly,
    require_finite,
    require_positive,
)
from .geodetic import LocalFrame

__all__ = ["SensorNetwork", "COINCIDENCE_TOLERANCE"]


def _rebuild(positions: Any, sigma_az: Any, sigma_el: Any, ndim: int, frame: Any) -> SensorNetwork:
    """Unpickling: the constructor (which copies), with the frame."""
    return SensorNetwork(positions, sigma_az, sigma_el, ndim, frame=frame)


#: Two sensors closer than this (metres) are the same point: triangulation from them is
#: degenerate, so the network is rejected.
COINCIDENCE_TOLERANCE = 1e-9


#: Accepted angle noise stds, radians. Below 1e-12 the information 1/σ² (≳ 1e24 per
#: measurement) overflows the fitter's sums at long ranges and covariances come back NaN;
#: above π an angle carries no information (a wrapped residual is at most π).
ANGLE_STD_RANGE = (1e-12, math.pi)


def _sigma_array(name: str, value: ArrayLike, n: int) -> NDArray[np.float64]:
    """Broadcast a scalar or per-sensor std to shape ``(n,)`` and check it lies in
    :data:`ANGLE_STD_RANGE`."""
    arr = as_float_array(name, value)
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    elif arr.shape != (n,):
        raise ValueError(f"{name}: expected a scalar or shape ({n},) (one per sensor), got {arr.shape}")
    require_finite(name, arr)
    require_positive(name, arr)
    low, high = ANGLE_STD_RANGE
    outside = np.flatnonzero((arr < low) | (arr > high))
    if outside.size:
        i = int(outside[0])
        raise ValueError(f"{name}[{i}] = {float(arr[i])!r} rad; an angle std must lie in [{low:g}, π]")
    return arr


def _check_distinct(positions: NDArray[np.float64]) -> None:
    """Reject two sensors closer than :data:`COINCIDENCE_TOLERANCE`."""
    pairs = cKDTree(positions).query_pairs(COINCIDENCE_TOLERANCE)
    if pairs:
        i, j = min(pairs)  # report the lowest pair so the message is deterministic
        dist = float(np.linalg.norm(positions[i] - positions[j]))
        raise ValueError(
            f"positions: sensors {i} and {j} are coincident (distance {dist!r} m < {COINCIDENCE_TOLERANCE} m)"
        )


@dataclass(frozen=True, eq=False)
class SensorNetwork:
    """A fixed set of passive (angle-only) sensors.

    Prefer the constructors :meth:`planar` (2-D, bearing only) and :meth:`spatial` (3-D,
    azimuth and elevation). The arrays are validated, copied and made read-only.

    Parameters
    ----------
    positions : array_like, shape (S, 3)
        Sensor positions in metres. For a 2-D network every z must be 0.
    sigma_azimuth : float or array_like, shape (S,)
        Azimuth (bearing) noise standard deviation per sensor, radians, > 0.
    sigma_elevation : float or array_like, shape (S,), optional
        Elevation noise standard deviation per sensor, radians, > 0. Required for a 3-D
        network; for a 2-D network omit it (or pass NaN) and NaN is stored.
    ndim : {2, 3}, optional
        Network dimension. Inferred when omitted: 3 if ``sigma_elevation`` is given and
        not all NaN, else 2.
    frame : LocalFrame, optional
        The geodetic East-North-Up frame the positions are in (set when the network was read
        from latitudes and longitudes): ``frame.to_geodetic`` takes any result's positions
        back to latitude, longitude and altitude.

    Attributes
    ----------
    positions : numpy.ndarray, shape (S, 3)
    sigma_azimuth : numpy.ndarray, shape (S,)
    sigma_elevation : numpy.ndarray, shape (S,)
        All NaN for a 2-D network.
    ndim : int

    Notes
    -----
    Sensors are static for now, but METHODS §0 asks that a sensor's position be a
    *function of time* in the data model so that moving platforms can be added without
    changing callers: algorithms must therefore ask :meth:`position_at` rather than index
    :attr:`positions` directly.
    """

    # Annotations give the types after validation; ``None`` defaults mean "omitted / infer"
    # and are replaced in __post_init__, so readers never see None.
    positions: NDArray[np.float64]
    sigma_azimuth: NDArray[np.float64]
    sigma_elevation: NDArray[np.float64] = None  # type: ignore[assignment]
    ndim: int = None  # type: ignore[assignment]
    frame: LocalFrame | None = field(default=None, kw_only=True)

    def __post_init__(self) -> None:
        if self.frame is not None and not isinstance(self.frame, LocalFrame):
            raise TypeError(f"frame: expected a LocalFrame, got {type(self.frame).__name__}")
        pos = as_float_array("positions", self.positions, ndim=2)
        if pos.shape[0] < 1:
            raise ValueError("positions: a network needs at least 1 sensor, got 0")
        if pos.shape[1] != 3:
            raise ValueError(
                f"positions: expected shape (S, 3), got {pos.shape} (use SensorNetwork.planar for (S, 2) positions)"
            )
        require_finite("positions", pos)
        n = pos.shape[0]
        ndim = self._resolve_ndim()
        sig_az = _sigma_array("sigma_azimuth", self.sigma_azimuth, n)
        if ndim == 3:
            if self.sigma_elevation is None:
                raise ValueError("sigma_elevation: required for a 3-D network")
            sig_el = _sigma_array("sigma_elevation", self.sigma_elevation, n)
        else:
            sig_el = self._planar_sigma_elevation(n)
            nonzero = np.flatnonzero(pos[:, 2] != 0.0)
            if nonzero.size:
                i = int(nonzero[0])
                raise ValueError(f"positions[{i}, 2] = {pos[i, 2].item()!r}; a 2-D network must have z = 0")
        _check_distinct(pos)
        object.__setattr__(self, "positions", readonly(pos))
        object.__setattr__(self, "sigma_azimuth", readonly(sig_az))
        object.__setattr__(self, "sigma_elevation", readonly(sig_el))
        object.__setattr__(self, "ndim", ndim)

    def _resolve_ndim(self) -> int:
        """Return the declared dimension, or infer it from ``sigma_elevation``."""
        if self.ndim is None:
            if self.sigma_elevation is None:
                return 2
            el = as_float_array("sigma_elevation", self.sigma_elevation)
            return 2 if el.size and bool(np.isnan(el).all()) else 3
        if isinstance(self.ndim, bool) or not isinstance(self.ndim, (int, np.integer)):
            raise TypeError(f"ndim: expected 2 or 3, got {self.ndim!r}")
        if self.ndim not in (2, 3):
            raise ValueError(f"ndim: expected 2 or 3, got {self.ndim}")
        return int(self.ndim)

    def _planar_sigma_elevation(self, n: int) -> NDArray[np.float64]:
        """A 2-D network stores NaN; a finite elevation std there is a caller mistake."""
        if self.sigma_elevation is not None:
            el = as_float_array("sigma_elevation", self.sigma_elevation)
            if not np.isnan(el).all():
                raise ValueError("sigma_elevation: must be omitted or NaN for a 2-D network")
        return np.full(n, np.nan)

    # ------------------------------------------------------------------ constructors
    @classmethod
    def planar(cls, positions_xy: ArrayLike, sigma_bearing: ArrayLike) -> SensorNetwork:
        """Build a 2-D bearing-only network.

        Parameters
        ----------
        positions_xy : array_like, shape (S, 2)
            Sensor positions (x, y) in metres.
        sigma_bearing : float or array_like, shape (S,)
            Bearing noise std in radians, one value for all sensors or one per sensor.

        Returns
        -------
        SensorNetwork
            With ``ndim == 2`` and z = 0.
        """
        xy = as_float_array("positions_xy", positions_xy, shape=(None, 2))
        pos = np.column_stack([xy, np.zeros(xy.shape[0])])
        return cls(pos, _sigma_array("sigma_bearing", sigma_bearing, xy.shape[0]), ndim=2)

    @classmethod
    def spatial(
        cls,
        positions_xyz: ArrayLike,
        sigma_azimuth: ArrayLike,
        sigma_elevation: ArrayLike,
    ) -> SensorNetwork:
        """Build a 3-D azimuth/elevation network.

        Parameters
        ----------
        positions_xyz : array_like, shape (S, 3)
            Sensor positions in metres.
        sigma_azimuth, sigma_elevation : float or array_like, shape (S,)
            Angle noise stds in radians, scalar or per sensor.

        Returns
        -------
        SensorNetwork
            With ``ndim == 3``.
        """
        pos = as_float_array("positions_xyz", positions_xyz, shape=(None, 3))
        n = pos.shape[0]
        return cls(
            pos,
            _sigma_array("sigma_azimuth", sigma_azimuth, n),
            _sigma_array("sigma_elevation", sigma_elevation, n),
            3,
        )

    # ------------------------------------------------------------------ queries
    @property
    def n_sensors(self) -> int:
        """Number of sensors S."""
        return int(self.positions.shape[0])

    def position_at(self, sensor_index: ArrayLike, time: ArrayLike) -> NDArray[np.float64]:
        """Position of sensor(s) at time(s).

        Sensors are static today, so ``time`` only has to be finite; the argument exists so
        that moving platforms can be added later without changing any caller (METHODS §0).

        Parameters
        ----------
        sensor_index : int or array_like of int
            Sensor indices in ``[0, S)``.
        time : float or array_like of float
            Times in seconds; broadcast against ``sensor_index``.

        Returns
        -------
        numpy.ndarray, shape ``broadcast(sensor_index, time).shape + (3,)``
            Positions in metres (a fresh, writable array).
        """
        idx = as_int_array("sensor_index", sensor_index)
        t = as_float_array("time", time)
        require_finite("time", t)
        bad = np.flatnonzero((idx < 0) | (idx >= self.n_sensors))
        if bad.size:
            value = int(idx.flat[int(bad[0])])
            raise ValueError(f"sensor_index: {value} is not a sensor of this network (valid: 0..{self.n_sensors - 1})")
        idx, _ = np.broadcast_arrays(idx, t)
        return self.positions[idx].copy()

    # ------------------------------------------------------------------ dunder
    # ------------------------------------------------------------------ files
    @classmethod
    def from_csv(cls, path: str | os.PathLike[str], *, frame: LocalFrame | None = None) -> SensorNetwork:
        r"""Read a sensor file: one row per sensor, columns ``sensor`` (optional id), ``x``,
        ``y``, ``z`` (3-D), ``sigma_azimuth`` and, in 3-D, ``sigma_elevation`` — radians, or
        degrees with a ``_deg`` suffix (:mod:`passive_assoc.data.sensor_files`).

        >>> import tempfile, pathlib
        >>> path = pathlib.Path(tempfile.mkdtemp()) / "sensors.csv"
        >>> _ = path.write_text("sensor,x,y,sigma_azimuth_deg\n1,20000,0,0.3\n0,-20000,0,0.3\n")
        >>> net = SensorNetwork.from_csv(path)
        >>> net.ndim, net.positions[:, 0].tolist(), round(float(net.sigma_azimuth[0]), 6)
        (2, [-20000.0, 20000.0], 0.005236)

        With ``lat``, ``lon`` [, ``alt``] columns in place of ``x``, ``y`` [, ``z``] the
        sensors are placed in ``frame``, or in a frame chosen around them, which the network
        keeps (:mod:`passive_assoc.data.geodetic`).
        """
        from .sensor_files import read_sensor_columns

        try:
            return cls._from_arguments(*read_sensor_columns(path, frame))
        except ValueError as err:
            where = repr(os.fspath(path))
            raise ValueError(str(err) if where in str(err) else f"{where}: {err}") from None

    def to_csv(self, path: str | os.PathLike[str]) -> None:
        """Write the network in :meth:`from_csv`'s format (radians), which reads back exactly."""
        from .sensor_files import write_sensor_columns

        write_sensor_columns(self.to_columns(), path)

    @classmethod
    def from_pandas(cls, df: Any) -> SensorNetwork:
        """A network from a DataFrame with :meth:`from_csv`'s columns."""
        from ._io import import_pandas
        from .sensor_files import network_arguments

        if not isinstance(df, import_pandas().DataFrame):
            raise TypeError(f"df: expected a pandas.DataFrame, got {type(df).__name__}")
        return cls._from_arguments(*network_arguments({str(c): df[c].to_numpy() for c in df.columns}, source="df"))

    def to_pandas(self) -> Any:
        """The network as a DataFrame in :meth:`from_csv`'s columns (radians)."""
        from ._io import import_pandas

        return import_pandas().DataFrame(self.to_columns())

    def to_columns(self) -> dict[str, NDArray[Any]]:
        """The network as named columns in radians (:meth:`from_csv`'s format): ``sensor``,
        ``x``, ``y``, [``z``], ``sigma_azimuth``, [``sigma_elevation``]."""
        out: dict[str, NDArray[Any]] = {
            "sensor": np.arange(self.n_sensors, dtype=np.int64),
            "x": self.positions[:, 0].copy(),
            "y": self.positions[:, 1].copy(),
        }
        if self.ndim == 3:
            out["z"] = self.positions[:, 2].copy()
        out["sigma_azimuth"] = self.sigma_azimuth.copy()
        if self.ndim == 3:
            out["sigma_elevation"] = self.sigma_elevation.copy()
        return out

    @classmethod
    def _from_arguments(
        cls,
        positions: NDArray[np.float64],
        sigma_az: NDArray[np.float64],
        sigma_el: NDArray[np.float64] | None,
        ndim: int,
        frame: LocalFrame | None = None,
    ) -> SensorNetwork:
        """A network from what a sensor file gives (:mod:`passive_assoc.data.sensor_files`)."""
        if sigma_el is None:
            return cls(positions, sigma_az, ndim=ndim, frame=frame)
        return cls(positions, sigma_az, sigma_el, ndim, frame=frame)

    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]:
        # Rebuilt through the constructor (copies): a transport's arrays may be unaligned.
        return (
            _rebuild,
            (self.positions.copy(), self.sigma_azimuth.copy(), self.sigma_elevation.copy(), self.ndim, self.frame),
        )

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, SensorNetwork):
            return NotImplemented
        return (
            self.ndim == other.ndim
            and np.array_equal(self.positions, other.positions)
            and np.array_equal(self.sigma_azimuth, other.sigma_azimuth)
            and np.array_equal(self.sigma_elevation, other.sigma_elevation, equal_nan=True)
            and self.frame == other.frame
        )

    # Arrays are not hashable and equality is by value: keep the class unhashable rather
    # than hash by identity, which would disagree with ``==``.
    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return (
            f"SensorNetwork(ndim={self.ndim}, n_sensors={self.n_sensors}, "
            f"positions={self.positions.tolist()!r}, "
            f"sigma_azimuth={self.sigma_azimuth.tolist()!r}, "
            f"sigma_elevation={self.sigma_elevation.tolist()!r})"
        )
