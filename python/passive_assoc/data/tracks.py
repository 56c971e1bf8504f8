"""Columnar table of track states: the input of track-to-track association (METHODS §4, §5).

One row per (source, track, time): ``source`` is the radar or sensor that made the track,
``track`` its id within that source, ``time`` (s), the ``position`` (m) and optionally the
``velocity`` (m/s) and ``acceleration`` (m/s²) of the state, its ``covariance`` over the
stacked state, and, for simulated data only, a hidden ``truth`` label (target index, or −1
for a false track) that no algorithm may read.

The stacked state is in *block* order, positions first (``x, y, z, vx, vy, vz, ax, ay, az``,
METHODS §0); :mod:`passive_assoc.data.conventions` converts to and from the interleaved order
of Stone Soup and MATLAB.

>>> import numpy as np
>>> tracks = TrackTable.from_arrays(
...     source=[0, 0, 1], track=[7, 7, 3], time=[0.0, 10.0, 0.0],
...     position=[[0.0, 0.0], [3000.0, 0.0], [10.0, 5.0]],
...     velocity=[[300.0, 0.0], [300.0, 0.0], [290.0, 1.0]],
... )
>>> tracks.ndim, tracks.state_dim, tracks.sources.tolist(), tracks.scan_times().tolist()
(2, 4, [0, 1], [0.0, 10.0])
>>> [(s, t, rows.tolist()) for s, t, rows in tracks.tracks()]
[(0, 7, [0, 1]), (1, 3, [2])]
>>> tracks.at(0.0).state
array([[  0.,   0., 300.,   0.],
       [ 10.,   5., 290.,   1.]])
"""

from __future__ import annotations

import itertools
import os
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._validation import as_float_array, as_float_scalar, as_int_array, as_int_scalar, readonly
from ._io import import_pandas, read_csv, write_csv
from ._track_checks import BLOCKS, SYMMETRY_TOLERANCE, check_order, sort_order, validated_columns
from ._track_columns import KEYS, block_names, covariance_names, split_columns

__all__ = ["TrackTable", "SYMMETRY_TOLERANCE"]

_INTEGER_COLUMNS = ("source", "track", "truth")


@dataclass(frozen=True, eq=False)
class TrackTable:
    """Immutable, validated, columnar table of track states, sorted by (source, track, time).

    Parameters
    ----------
    source : array_like of int, shape (N,)
        Which radar or sensor made the track, >= 0.
    track : array_like of int, shape (N,)
        Track id within its source, >= 0 (the pair (source, track) names a track).
    time : array_like of float, shape (N,)
        Time of the state, seconds, finite.
    position : array_like of float, shape (N, ndim)
        Position, metres, ndim 1, 2 or 3 (a plain (N,) vector is a 1-D track).
    velocity, acceleration : array_like of float, shape (N, ndim), optional
        Velocity (m/s) and acceleration (m/s²); acceleration needs velocity, so the state is
        [position], [position, velocity] or [position, velocity, acceleration].
    covariance : array_like of float, shape (N, d, d), optional
        Covariance of the stacked state in block order (``x, y, vx, vy, ...``),
        ``d = ndim × blocks``; symmetric to :data:`SYMMETRY_TOLERANCE` (stored exactly
        symmetric), variances >= 0.
    truth : array_like of int, shape (N,), optional
        Hidden truth label: target index, or -1 for a false track. Algorithms never read it.

    Raises
    ------
    ValueError
        Naming the column and its first bad row: wrong shapes, NaN or inf, bad covariance,
        rows not sorted by (source, track, time) or a (source, track, time) twice. Build
        unsorted data with ``from_arrays(..., sort=True)``.

    Notes
    -----
    Scans are synchronous: the sources report their tracks at common times (the topology
    experiment's 10 s scans), so :meth:`at` matches times exactly. Tracks of asynchronous
    sources must be predicted to common times first. Arrays are copied and made read-only;
    an empty table (N = 0) is valid.
    """

    source: NDArray[np.int64]
    track: NDArray[np.int64]
    time: NDArray[np.float64]
    position: NDArray[np.float64]
    velocity: NDArray[np.float64] | None = None
    acceleration: NDArray[np.float64] | None = None
    covariance: NDArray[np.float64] | None = None
    truth: NDArray[np.int64] | None = None

    def __post_init__(self) -> None:
        columns = validated_columns(
            self.source,
            self.track,
            self.time,
            self.position,
            self.velocity,
            self.acceleration,
            self.covariance,
            self.truth,
        )
        check_order(columns)
        for name, value in columns.items():
            object.__setattr__(self, name, None if value is None else readonly(value))

    # ------------------------------------------------------------------ construction
    @classmethod
    def from_arrays(
        cls,
        source: ArrayLike,
        track: ArrayLike,
        time: ArrayLike,
        position: ArrayLike,
        velocity: ArrayLike | None = None,
        acceleration: ArrayLike | None = None,
        covariance: ArrayLike | None = None,
        truth: ArrayLike | None = None,
        *,
        sort: bool = False,
    ) -> TrackTable:
        """Build a table from column arrays (see the class docstring for each column).

        With ``sort=True`` the rows are first put in (source, track, time) order (stable);
        a (source, track, time) given twice is still an error, naming both original rows.
        """
        if not sort:
            return cls(source, track, time, position, velocity, acceleration, covariance, truth)  # type: ignore[arg-type]
        columns = validated_columns(source, track, time, position, velocity, acceleration, covariance, truth)
        order = sort_order(columns)
        return cls._of_columns({name: None if value is None else value[order] for name, value in columns.items()})

    @classmethod
    def _of_columns(cls, columns: Mapping[str, Any]) -> TrackTable:
        """The table of a mapping column name → array (the names of the dataclass fields)."""
        return cls(**columns)

    @classmethod
    def from_states(
        cls,
        source: ArrayLike,
        track: ArrayLike,
        time: ArrayLike,
        state: ArrayLike,
        ndim: int,
        covariance: ArrayLike | None = None,
        truth: ArrayLike | None = None,
        *,
        sort: bool = False,
    ) -> TrackTable:
        """Build a table from stacked block-order states ``(N, d)``, as a filter returns them.

        ``d / ndim`` (1, 2 or 3) is the number of blocks: position, + velocity, + acceleration.
        """
        ndim = as_int_scalar("ndim", ndim, minimum=1)
        states = as_float_array("state", state, ndim=2)
        if ndim > 3 or states.shape[1] not in (ndim, 2 * ndim, 3 * ndim):
            raise ValueError(
                f"state: expected shape (N, d), d = ndim × blocks (ndim = {ndim}, 1 to 3 blocks), got {states.shape}"
            )
        n_blocks = states.shape[1] // ndim
        velocity = states[:, ndim : 2 * ndim] if n_blocks >= 2 else None
        acceleration = states[:, 2 * ndim :] if n_blocks == 3 else None
        return cls.from_arrays(
            source, track, time, states[:, :ndim], velocity, acceleration, covariance, truth, sort=sort
        )

    # ------------------------------------------------------------------ shape of the data
    def __len__(self) -> int:
        return int(self.source.shape[0])

    @property
    def ndim(self) -> int:
        """Number of spatial axes, 1, 2 or 3."""
        return int(self.position.shape[1])

    @property
    def blocks(self) -> tuple[str, ...]:
        """The state blocks present, in stacking order: ``("position", "velocity", ...)``."""
        return tuple(name for name in BLOCKS if getattr(self, name) is not None)

    @property
    def state_dim(self) -> int:
        """Length d of the stacked state, ``ndim × len(blocks)``."""
        return self.ndim * len(self.blocks)

    @property
    def state(self) -> NDArray[np.float64]:
        """The stacked state ``(N, d)`` in block order (x, y, vx, vy, ...), read-only."""
        stacked = np.hstack([getattr(self, name) for name in self.blocks])
        return readonly(stacked)

    @property
    def sources(self) -> NDArray[np.int64]:
        """The distinct sources, ascending."""
        return np.unique(self.source)

    def scan_times(self) -> NDArray[np.float64]:
        """The distinct times, ascending (one per synchronous scan)."""
        return np.unique(self.time)

    # ------------------------------------------------------------------ views
    def select(self, indices: ArrayLike) -> TrackTable:
        """New table of the given rows, kept in table order (so it stays sorted).

        Parameters
        ----------
        indices : array_like of int, or of bool with length N
            Row indices in ``[0, N)``, each at most once, or a mask.
        """
        arr = np.asarray(indices)
        if arr.dtype.kind == "b":
            if arr.shape != (len(self),):
                raise ValueError(f"indices: boolean mask has shape {arr.shape}, expected ({len(self)},)")
            rows = np.flatnonzero(arr)
        else:
            idx = as_int_array("indices", arr, ndim=1)
            bad = (idx < 0) | (idx >= len(self))
            if bad.any():
                i = int(np.flatnonzero(bad)[0])
                raise ValueError(f"indices[{i}] = {idx[i]} is out of range for a table of {len(self)} rows")
            rows = np.sort(idx)
            if (np.diff(rows) == 0).any():
                raise ValueError(f"indices: row {rows[np.flatnonzero(np.diff(rows) == 0)[0]]} is given twice")
        return self._of_columns(
            {name: None if value is None else value[rows] for name, value in self._columns().items()}
        )

    def at(self, time: float) -> TrackTable:
        """The rows of the scan at exactly ``time`` (empty if no track has that time)."""
        return self.select(self.time == as_float_scalar("time", time, finite=True))

    def of(self, source: int) -> TrackTable:
        """The rows of one source (empty if it has none)."""
        return self.select(self.source == as_int_scalar("source", source))

    def tracks(self) -> Iterator[tuple[int, int, NDArray[np.int64]]]:
        """Each track in table order as ``(source, track, rows)``, rows ascending in time."""
        n = len(self)
        if n == 0:
            return
        starts = np.flatnonzero((self.source[1:] != self.source[:-1]) | (self.track[1:] != self.track[:-1])) + 1
        bounds = np.concatenate([[0], starts, [n]])
        for start, stop in itertools.pairwise(bounds):
            yield int(self.source[start]), int(self.track[start]), np.arange(start, stop, dtype=np.int64)

    def _columns(self) -> dict[str, Any]:
        return {name: getattr(self, name) for name in (*KEYS, *BLOCKS, "covariance", "truth")}

    # ------------------------------------------------------------------ flat columns and I/O
    def to_arrays(self) -> dict[str, NDArray[Any]]:
        """Writable flat columns: source, track, time, x[, y[, z]], [vx.., [ax..]],
        [cov_i_j for i <= j (upper triangle, state indices in block order)], [truth]."""
        out: dict[str, NDArray[Any]] = {name: getattr(self, name).copy() for name in KEYS}
        for block in self.blocks:
            values = getattr(self, block)
            out.update({name: values[:, k].copy() for k, name in enumerate(block_names(block, self.ndim))})
        if self.covariance is not None:
            out.update({name: self.covariance[:, i, j].copy() for i, j, name in covariance_names(self.state_dim)})
        if self.truth is not None:
            out["truth"] = self.truth.copy()
        return out

    @classmethod
    def from_columns(cls, columns: Mapping[str, ArrayLike], *, sort: bool = False) -> TrackTable:
        """Inverse of :meth:`to_arrays` (any column order).

        Raises
        ------
        ValueError
            If a required column is missing (source, track, time, x), a block or the
            covariance is incomplete, or a column is unknown.
        """
        return cls.from_arrays(**split_columns(columns), sort=sort)

    def to_csv(self, path: str | os.PathLike[str]) -> None:
        """Write the columns of :meth:`to_arrays` as CSV with a header; floats exact (``repr``)."""
        write_csv(path, self.to_arrays())

    @classmethod
    def from_csv(cls, path: str | os.PathLike[str], *, sort: bool = False) -> TrackTable:
        """Read a table written by :meth:`to_csv` (or any CSV with those columns); every
        error names the file."""
        columns = read_csv(path, _INTEGER_COLUMNS)
        try:
            return cls.from_columns(columns, sort=sort)
        except ValueError as err:
            raise ValueError(f"{err} (file {os.fspath(path)!r})") from None

    def to_pandas(self) -> Any:
        """A :class:`pandas.DataFrame` of :meth:`to_arrays` (pandas is optional: ImportError)."""
        return import_pandas().DataFrame(self.to_arrays())

    @classmethod
    def from_pandas(cls, df: Any, *, sort: bool = False) -> TrackTable:
        """Build a table from a DataFrame with the columns of :meth:`to_arrays`."""
        if not isinstance(df, import_pandas().DataFrame):
            raise TypeError(f"df: expected a pandas.DataFrame, got {type(df).__name__}")
        return cls.from_columns({str(c): df[c].to_numpy() for c in df.columns}, sort=sort)

    # ------------------------------------------------------------------ dunder
    def __eq__(self, other: object) -> bool:
        if not isinstance(other, TrackTable):
            return NotImplemented
        mine, theirs = self.to_arrays(), other.to_arrays()
        return mine.keys() == theirs.keys() and all(
            mine[k].dtype == theirs[k].dtype and np.array_equal(mine[k], theirs[k]) for k in mine
        )

    __hash__ = None  # type: ignore[assignment]  # value equality over arrays

    def __repr__(self) -> str:
        return (
            f"TrackTable(n_rows={len(self)}, ndim={self.ndim}, blocks={self.blocks}, "
            f"covariance={self.covariance is not None}, sources={self.sources.tolist()}, "
            f"n_tracks={sum(1 for _ in self.tracks())}, truth={self.truth is not None})"
        )
