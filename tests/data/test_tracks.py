"""Tests of TrackTable and the state-vector conventions."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import passive_assoc as pa
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from passive_assoc.data import (
    SYMMETRY_TOLERANCE,
    TrackTable,
    covariance_from_interleaved,
    covariance_to_interleaved,
    from_interleaved,
    interleaved_order,
    to_interleaved,
)


def _covariances(rng: np.random.Generator, n: int, d: int) -> np.ndarray:
    a = rng.normal(size=(n, d, d))
    return a @ a.transpose(0, 2, 1) + d * np.eye(d)


def _table(ndim: int = 2, blocks: int = 3, covariance: bool = True, truth: bool = True) -> TrackTable:
    """Two sources: source 0 has tracks 4 (3 scans) and 9 (2 scans), source 1 track 0 (3 scans)."""
    rng = np.random.default_rng(ndim * 10 + blocks)
    source = np.array([0, 0, 0, 0, 0, 1, 1, 1])
    track = np.array([4, 4, 4, 9, 9, 0, 0, 0])
    time = np.array([0.0, 10.0, 20.0, 10.0, 20.0, 0.0, 10.0, 20.0])
    n = source.size
    vectors = [rng.normal(0, 1e4, (n, ndim)) for _ in range(blocks)]
    return TrackTable.from_arrays(
        source,
        track,
        time,
        vectors[0],
        vectors[1] if blocks > 1 else None,
        vectors[2] if blocks > 2 else None,
        _covariances(rng, n, ndim * blocks) if covariance else None,
        rng.integers(-1, 3, n) if truth else None,
    )


def _bitwise_equal(a: TrackTable, b: TrackTable) -> bool:
    x, y = a.to_arrays(), b.to_arrays()
    return x.keys() == y.keys() and all(x[k].dtype == y[k].dtype and x[k].tobytes() == y[k].tobytes() for k in x)


# --------------------------------------------------------------------------- basics and views


def test_table_basics() -> None:
    t = _table()
    assert len(t) == 8 and t.ndim == 2 and t.blocks == ("position", "velocity", "acceleration")
    assert t.state_dim == 6 and t.state.shape == (8, 6)
    assert np.array_equal(t.state, np.hstack([t.position, t.velocity, t.acceleration]))
    assert t.source.dtype == np.int64 and t.track.dtype == np.int64 and t.truth is not None
    assert t.sources.tolist() == [0, 1] and t.scan_times().tolist() == [0.0, 10.0, 20.0]
    for column in (t.position, t.covariance, t.state):
        with pytest.raises(ValueError, match="read-only"):
            column[0, 0] = 0.0  # type: ignore[index]
    assert pa.TrackTable is TrackTable
    assert "n_tracks=3" in repr(t)
    empty = TrackTable.from_arrays([], [], [], np.zeros((0, 3)))
    assert len(empty) == 0 and empty.ndim == 3 and list(empty.tracks()) == [] and empty.scan_times().size == 0


def test_one_d_positions_may_be_plain_vectors() -> None:
    t = TrackTable.from_arrays([0, 0], [1, 1], [0.0, 1.0], [5.0, 6.0], velocity=[1.0, 1.0])
    assert t.ndim == 1 and t.position.shape == (2, 1) and t.state.tolist() == [[5.0, 1.0], [6.0, 1.0]]


def test_views() -> None:
    t = _table()
    scan = t.at(10.0)
    assert len(scan) == 3 and np.all(scan.time == 10.0)
    assert list(zip(scan.source.tolist(), scan.track.tolist(), strict=True)) == [(0, 4), (0, 9), (1, 0)]
    assert len(t.at(0.0)) == 2 and len(t.at(5.0)) == 0
    assert len(t.of(0)) == 5 and np.all(t.of(1).track == 0) and len(t.of(7)) == 0
    assert [(s, k, rows.tolist()) for s, k, rows in t.tracks()] == [
        (0, 4, [0, 1, 2]),
        (0, 9, [3, 4]),
        (1, 0, [5, 6, 7]),
    ]
    # A view keeps every column of its rows, covariance and truth included.
    rows = np.flatnonzero(t.time == 10.0)
    assert np.array_equal(scan.covariance, t.covariance[rows])  # type: ignore[index]
    assert np.array_equal(scan.truth, t.truth[rows])  # type: ignore[index]


def test_select_keeps_table_order() -> None:
    t = _table()
    assert t.select([6, 1]).track.tolist() == [4, 0]  # rows 1 and 6, in table order
    assert len(t.select(t.source == 1)) == 3
    with pytest.raises(ValueError, match=r"^indices: row 2 is given twice"):
        t.select([2, 5, 2])
    with pytest.raises(ValueError, match=r"^indices\[1\] = 8 is out of range"):
        t.select([0, 8])
    with pytest.raises(ValueError, match=r"^indices: boolean mask has shape \(2,\)"):
        t.select([True, False])


def test_from_states_splits_the_blocks() -> None:
    t = _table(ndim=3, blocks=2)
    back = TrackTable.from_states(t.source, t.track, t.time, t.state, ndim=3, covariance=t.covariance, truth=t.truth)
    assert back == t and back.blocks == ("position", "velocity")
    with pytest.raises(ValueError, match=r"^state: expected shape \(N, d\)"):
        TrackTable.from_states([0], [0], [0.0], np.zeros((1, 5)), ndim=2)


# --------------------------------------------------------------------------- order


def test_sort_puts_rows_in_order() -> None:
    t = _table()
    perm = np.random.default_rng(3).permutation(len(t))
    a = t.to_arrays()
    shuffled = {name: value[perm] for name, value in a.items()}
    with pytest.raises(ValueError, match=r"sorts before row .* pass sort=True"):
        TrackTable.from_columns(shuffled)
    assert _bitwise_equal(TrackTable.from_columns(shuffled, sort=True), t)


@pytest.mark.parametrize(
    ("source", "track", "time", "pattern"),
    [
        ([1, 0, 0], [0, 0, 1], [0.0, 0.0, 0.0], r"^row 1 \(source, track, time\) = \(0, 0, 0\.0\) sorts before row 0"),
        ([0, 0, 0], [2, 1, 1], [0.0, 0.0, 1.0], r"^row 1 .* = \(0, 1, 0\.0\) sorts before row 0"),
        ([0, 0, 0], [1, 1, 1], [0.0, 2.0, 1.0], r"^row 2 .* = \(0, 1, 1\.0\) sorts before row 1"),
        (
            [0, 0, 1],
            [1, 1, 1],
            [0.0, 0.0, 0.0],
            r"^rows 0 and 1 have the same \(source, track, time\) = \(0, 1, 0\.0\)",
        ),
    ],
)
def test_unsorted_or_duplicate_rows_are_named(source, track, time, pattern) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(ValueError, match=pattern):
        TrackTable.from_arrays(source, track, time, np.zeros((3, 2)))


def test_sort_reports_duplicates_by_original_row() -> None:
    with pytest.raises(ValueError, match=r"^rows 0 and 3 have the same \(source, track, time\) = \(2, 5, 1\.0\)"):
        TrackTable.from_arrays([2, 0, 1, 2], [5, 0, 0, 5], [1.0, 0.0, 0.0, 1.0], np.zeros((4, 1)), sort=True)


def test_same_time_in_different_tracks_is_fine() -> None:
    t = TrackTable.from_arrays([0, 0, 1], [0, 1, 0], [5.0, 5.0, 5.0], np.zeros((3, 2)))
    assert len(t.at(5.0)) == 3 and len(list(t.tracks())) == 3


# --------------------------------------------------------------------------- validation

_BASE = {"source": [0, 0, 1], "track": [0, 0, 0], "time": [0.0, 1.0, 0.0], "position": np.zeros((3, 2))}
_SPD = np.broadcast_to(np.eye(4), (3, 4, 4))


def _with(matrix_row1: np.ndarray) -> np.ndarray:
    cov = _SPD.copy()
    cov[1] = matrix_row1
    return cov


_ASYMMETRIC = np.eye(4)
_ASYMMETRIC[0, 3] = 0.5
_NEGATIVE = np.eye(4)
_NEGATIVE[2, 2] = -1.0


@pytest.mark.parametrize(
    ("kwargs", "exc", "pattern"),
    [
        ({"source": [0, -1, 1]}, ValueError, r"^source\[1\] = -1; source indices must be >= 0"),
        ({"track": [0, -2, 0]}, ValueError, r"^track\[1\] = -2; track ids must be >= 0"),
        ({"track": [0, 0.5, 0]}, ValueError, r"^track\[1\] = 0\.5 is not an integer"),
        ({"source": ["a", "b", "c"]}, TypeError, r"^source: expected integers"),
        ({"time": [0.0, 1.0]}, ValueError, r"^time: has length 2 but source has length 3"),
        ({"time": [0.0, np.nan, 1.0]}, ValueError, r"^time\[1\] = nan; all values must be finite"),
        ({"position": np.zeros((3, 4))}, ValueError, r"^position: expected shape \(N, ndim\) with ndim 1, 2 or 3"),
        ({"position": np.zeros((2, 2))}, ValueError, r"^position: has length 2 but source has length 3"),
        ({"position": [[0, 0], [0, np.inf], [0, 0]]}, ValueError, r"^position\[1, 1\] = inf"),
        ({"velocity": np.zeros((3, 3))}, ValueError, r"^velocity: expected shape \(3, 2\) like position"),
        ({"velocity": [[0, 0], [0, 0], [np.nan, 0]]}, ValueError, r"^velocity\[2, 0\] = nan"),
        ({"acceleration": np.zeros((3, 2))}, ValueError, r"^acceleration: given without velocity"),
        (
            {"velocity": np.zeros((3, 2)), "covariance": np.zeros((3, 2, 2))},
            ValueError,
            r"^covariance: expected shape \(3, 4, 4\)",
        ),
        (
            {"velocity": np.zeros((3, 2)), "covariance": _with(_ASYMMETRIC)},
            ValueError,
            r"^covariance\[1\] is not symmetric",
        ),
        (
            {"velocity": np.zeros((3, 2)), "covariance": _with(_NEGATIVE)},
            ValueError,
            r"^covariance\[1, 2, 2\] = -1\.0; a variance",
        ),
        (
            {"velocity": np.zeros((3, 2)), "covariance": _with(np.full((4, 4), np.nan))},
            ValueError,
            r"^covariance\[1, 0, 0\] = nan",
        ),
        ({"truth": [0, -2, 1]}, ValueError, r"^truth\[1\] = -2; labels are target indices"),
        ({"truth": [0, 1]}, ValueError, r"^truth: has length 2"),
    ],
)
def test_rejects_bad_input(kwargs, exc, pattern) -> None:  # type: ignore[no-untyped-def]
    with pytest.raises(exc, match=pattern):
        TrackTable.from_arrays(**{**_BASE, **kwargs})


def test_nearly_symmetric_covariance_is_stored_symmetric() -> None:
    cov = np.broadcast_to(np.eye(2) * 1e6, (3, 2, 2)).copy()
    cov[0, 0, 1], cov[0, 1, 0] = 1.0, 1.0 + 1e6 * SYMMETRY_TOLERANCE / 2
    t = TrackTable.from_arrays(**{**_BASE, "position": np.zeros((3, 1)), "velocity": np.zeros((3, 1))}, covariance=cov)
    assert t.covariance is not None and np.array_equal(t.covariance, t.covariance.transpose(0, 2, 1))


def test_huge_symmetric_covariance_stays_finite() -> None:
    """Entries near the float64 limit stay finite when made exactly symmetric (a plain
    ``(C + Cᵀ) / 2`` overflows to inf)."""
    cov = np.broadcast_to(np.array([[1.5e308, 1e308], [1e308, 1.5e308]]), (3, 2, 2)).copy()
    t = TrackTable.from_arrays(**{**_BASE, "position": np.zeros((3, 2))}, covariance=cov)
    assert t.covariance is not None and np.array_equal(t.covariance, cov)


# --------------------------------------------------------------------------- files and frames


@pytest.mark.parametrize(("ndim", "blocks"), [(1, 1), (1, 3), (2, 2), (3, 1), (3, 3)])
@pytest.mark.parametrize("extras", [True, False])
def test_csv_round_trip_exact(tmp_path: Path, ndim: int, blocks: int, extras: bool) -> None:
    t = _table(ndim, blocks, covariance=extras, truth=extras)
    path = tmp_path / "tracks.csv"
    t.to_csv(path)
    header = path.read_text().splitlines()[0].split(",")
    d = ndim * blocks
    assert header[:4] == ["source", "track", "time", "x"]
    assert sum(name.startswith("cov_") for name in header) == (d * (d + 1) // 2 if extras else 0)
    assert ("truth" in header) == extras and (header[-1] == "truth") == extras
    back = TrackTable.from_csv(path)
    assert _bitwise_equal(back, t) and back == t


def test_csv_header_names() -> None:
    names = list(_table(ndim=2, blocks=2).to_arrays())
    assert names[:11] == ["source", "track", "time", "x", "y", "vx", "vy", "cov_0_0", "cov_0_1", "cov_0_2", "cov_0_3"]
    assert names[-2:] == ["cov_3_3", "truth"] and len(names) == 3 + 4 + 10 + 1


finite = st.floats(allow_nan=False, allow_infinity=False)


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 2**40), finite, finite), max_size=15, unique_by=lambda r: r[0]))
def test_csv_round_trip_any_double(tmp_path_factory: pytest.TempPathFactory, rows) -> None:  # type: ignore[no-untyped-def]
    tracks = sorted(r[0] for r in rows)
    values = {r[0]: r[1:] for r in rows}
    table = TrackTable.from_arrays(
        np.zeros(len(rows), dtype=np.int64),
        tracks,
        [values[k][0] for k in tracks],
        np.array([values[k][1] for k in tracks]).reshape(-1, 1),
    )
    path = tmp_path_factory.mktemp("csv") / "t.csv"
    table.to_csv(path)
    assert _bitwise_equal(table, TrackTable.from_csv(path))


def test_from_csv_reports_bad_content(tmp_path: Path) -> None:
    path = tmp_path / "bad.csv"
    cases = {
        "source,track,time,x\n0,0,0.0,q\n": r"^x: line 2 has 'q', not a number",
        "source,track,time,x,vx\n0,1.5,0.0,1.0,2.0\n": r"^track: line 2 has '1\.5', not an integer",
        "source,track,time,y\n0,0,0.0,1.0\n": r"^columns: missing required column 'x'",
        "source,track,time,x,z\n0,0,0.0,1.0,2.0\n": r"^columns: position needs x, then y, then z",
        "source,track,time,x,y,vx\n0,0,0.0,1.0,2.0,3.0\n": r"^columns: velocity needs \['vx', 'vy'\], missing \['vy'\]",
        "source,track,time,x,cov_0_1\n0,0,0.0,1.0,2.0\n": r"^columns: unknown column 'cov_0_1'",
        "source,track,time,x,vx,cov_0_0,cov_1_1\n0,0,0.0,1.0,2.0,1.0,1.0\n": r"missing \['cov_0_1'\]",
        "source,track,time,x,bogus\n0,0,0.0,1.0,2.0\n": r"^columns: unknown column 'bogus'",
        "source,track,time,x\n0,0,0.0\n": r"^path: line 2 has 3 fields",
        "source,track,time,x\n0,0,1.0,1.0\n0,0,0.0,1.0\n": r"^row 1 .* sorts before row 0",
    }
    for text, pattern in cases.items():
        path.write_text(text)
        with pytest.raises(ValueError, match=pattern) as raised:
            TrackTable.from_csv(path)
        assert str(raised.value).endswith(f"(file {str(path)!r})"), raised.value  # every error names the file
    path.write_text("source,track,time,x\n0,0,1.0,1.0\n0,0,0.0,2.0\n")
    assert TrackTable.from_csv(path, sort=True).position.ravel().tolist() == [2.0, 1.0]


def test_pandas_round_trip() -> None:
    pytest.importorskip("pandas")
    t = _table(3, 3)
    df = t.to_pandas()
    assert list(df.columns)[:6] == ["source", "track", "time", "x", "y", "z"] and len(df) == 8
    assert _bitwise_equal(TrackTable.from_pandas(df), t)
    reversed_rows = df.iloc[::-1].reset_index(drop=True)
    assert _bitwise_equal(TrackTable.from_pandas(reversed_rows, sort=True), t)
    with pytest.raises(TypeError, match=r"^df: expected a pandas.DataFrame"):
        TrackTable.from_pandas({"source": [0]})


def test_pandas_missing_gives_install_hint(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "pandas", None)  # makes `import pandas` fail
    with pytest.raises(ImportError, match=r"pip install passive-assoc\[pandas\]"):
        _table().to_pandas()


# --------------------------------------------------------------------------- conventions


def test_interleaved_order_is_the_stone_soup_layout() -> None:
    # (x, y, z, vx, vy, vz) → (x, vx, y, vy, z, vz)
    assert interleaved_order(3, 2).tolist() == [0, 3, 1, 4, 2, 5]
    # (x, y, vx, vy, ax, ay) → (x, vx, ax, y, vy, ay)
    assert interleaved_order(2, 3).tolist() == [0, 2, 4, 1, 3, 5]
    assert interleaved_order(1, 3).tolist() == [0, 1, 2] and interleaved_order(3, 1).tolist() == [0, 1, 2]
    names = np.array(["x", "y", "z", "vx", "vy", "vz", "ax", "ay", "az"])
    assert names[interleaved_order(3, 3)].tolist() == ["x", "vx", "ax", "y", "vy", "ay", "z", "vz", "az"]


@pytest.mark.parametrize(("ndim", "blocks"), [(1, 2), (2, 2), (2, 3), (3, 2), (3, 3)])
def test_conventions_round_trip(ndim: int, blocks: int) -> None:
    t = _table(ndim, blocks)
    states, covs = t.state, t.covariance
    assert covs is not None
    inter = to_interleaved(states, ndim, blocks)
    inter_cov = covariance_to_interleaved(covs, ndim, blocks)
    # Position axis k sits at k * blocks in the interleaved vector, velocity right after it.
    assert np.array_equal(inter[:, 1], states[:, ndim])
    assert inter_cov[0, 0, 1] == covs[0, 0, ndim]
    if ndim > 1:
        assert np.array_equal(inter[:, blocks], states[:, 1])
        assert inter_cov[0, 1, blocks] == covs[0, ndim, 1]
    # Variances move with their component; the matrix stays symmetric.
    assert np.array_equal(
        np.diagonal(inter_cov, axis1=1, axis2=2), to_interleaved(np.diagonal(covs, axis1=1, axis2=2), ndim, blocks)
    )
    assert np.array_equal(inter_cov, inter_cov.transpose(0, 2, 1))
    assert np.array_equal(from_interleaved(inter, ndim, blocks), states)
    assert np.array_equal(covariance_from_interleaved(inter_cov, ndim, blocks), covs)
    # One state or one matrix works as well as a batch.
    assert np.array_equal(to_interleaved(states[0], ndim, blocks), inter[0])
    assert np.array_equal(covariance_to_interleaved(covs[0], ndim, blocks), inter_cov[0])


def test_conventions_reject_bad_layouts() -> None:
    with pytest.raises(ValueError, match=r"^state: expected shape \(\.\.\., 6\)"):
        to_interleaved(np.zeros(4), 3, 2)
    with pytest.raises(ValueError, match=r"^covariance: expected shape \(\.\.\., 4, 4\)"):
        covariance_from_interleaved(np.zeros((4, 3)), 2, 2)
    with pytest.raises(ValueError, match=r"^ndim: expected 1, 2 or 3"):
        interleaved_order(4, 1)
    with pytest.raises(ValueError, match=r"^blocks: expected 1 \(position\)"):
        interleaved_order(2, 4)
    with pytest.raises(TypeError, match=r"^ndim: expected an int"):
        interleaved_order(2.0, 1)  # type: ignore[arg-type]
