"""Tests of MeasurementTable."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from passive_assoc.data import MeasurementTable, SensorNetwork, TrackTable


def _table(n: int = 5, truth: bool = True, elevation: bool = True) -> MeasurementTable:
    rng = np.random.default_rng(0)
    return MeasurementTable.from_arrays(
        sensor=rng.integers(0, 2, n),
        time=rng.uniform(0, 100, n),
        azimuth=rng.uniform(-np.pi, np.pi, n),
        elevation=rng.uniform(0, 1, n) if elevation else None,
        attributes={"rf": rng.normal(4000, 10, n), "pw": rng.normal(5, 0.2, n)},
        truth=rng.integers(-1, 3, n) if truth else None,
    )


def _bitwise_equal(a: MeasurementTable, b: MeasurementTable) -> bool:
    x, y = a.to_arrays(), b.to_arrays()
    return x.keys() == y.keys() and all(x[k].dtype == y[k].dtype and x[k].tobytes() == y[k].tobytes() for k in x)


def test_table_basics() -> None:
    t = _table()
    assert len(t) == 5 and t.ndim == 3
    assert t.sensor.dtype == np.int64 and t.truth is not None and t.truth.dtype == np.int64
    with pytest.raises(ValueError, match="read-only"):
        t.azimuth[0] = 0.0
    with pytest.raises(TypeError):
        t.attributes["new"] = np.zeros(5)  # type: ignore[index]
    arrays = t.to_arrays()
    assert set(arrays) == {"sensor", "time", "azimuth", "elevation", "truth", "attr_rf", "attr_pw"}
    arrays["time"][0] = -1.0  # writable copies, the table is unchanged
    assert t.time[0] != -1.0
    assert MeasurementTable.from_columns(t.to_arrays()) == t
    planar = _table(elevation=False)
    assert planar.ndim == 2 and np.all(np.isnan(planar.elevation))
    empty = MeasurementTable.from_arrays([], [], [])
    assert len(empty) == 0 and empty.ndim == 2


@pytest.mark.parametrize(
    ("kwargs", "exc", "pattern"),
    [
        ({"time": [0.0, 1.0]}, ValueError, r"^time: has length 2 but sensor has length 3"),
        ({"azimuth": [0.0, np.inf, 0.0]}, ValueError, r"^azimuth\[1\] = inf"),
        ({"time": [0.0, 1.0, np.nan]}, ValueError, r"^time\[2\] = nan"),
        ({"sensor": [0, -1, 0]}, ValueError, r"^sensor\[1\] = -1; sensor indices must be >= 0"),
        ({"sensor": [0, 0.5, 0]}, ValueError, r"^sensor\[1\] = 0\.5 is not an integer"),
        ({"sensor": ["a", "b", "c"]}, TypeError, r"^sensor: expected integers"),
        ({"elevation": [0.1, np.nan, 0.2]}, ValueError, r"^elevation\[1\] = nan; .*all finite"),
        ({"elevation": [np.nan, 0.3, np.nan]}, ValueError, r"^elevation\[1\] = 0\.3"),
        ({"elevation": [0.1, -np.inf, 0.2]}, ValueError, r"^elevation\[1\] = -inf"),
        ({"truth": [0, -2, 1]}, ValueError, r"^truth\[1\] = -2"),
        ({"truth": [0, 1]}, ValueError, r"^truth: has length 2"),
        ({"attributes": {"rf": [1.0, 2.0]}}, ValueError, r"^attributes\['rf'\]: has length 2"),
        ({"attributes": {"rf": [1.0, np.nan, 2.0]}}, ValueError, r"^attributes\['rf'\]\[1\] = nan"),
        ({"attributes": {"a,b": [1.0, 2.0, 3.0]}}, ValueError, r"^attributes: invalid name"),
        ({"attributes": {3: [1.0, 2.0, 3.0]}}, TypeError, r"^attributes: names must be str"),
        ({"azimuth": [[0.0, 1.0, 2.0]]}, ValueError, r"^azimuth: expected a 1-dimensional"),
    ],
)
def test_table_rejects_bad_input(kwargs, exc, pattern) -> None:  # type: ignore[no-untyped-def]
    base = {"sensor": [0, 1, 0], "time": [0.0, 1.0, 2.0], "azimuth": [0.1, 0.2, 0.3]}
    with pytest.raises(exc, match=pattern):
        MeasurementTable.from_arrays(**{**base, **kwargs})


@pytest.mark.parametrize("truth", [True, False])
@pytest.mark.parametrize("elevation", [True, False])
def test_csv_round_trip_exact(tmp_path: Path, truth: bool, elevation: bool) -> None:
    t = _table(50, truth=truth, elevation=elevation)
    path = tmp_path / "m.csv"
    t.to_csv(path)
    header = path.read_text().splitlines()[0].split(",")
    assert header[:4] == ["sensor", "time", "azimuth", "elevation"]
    assert ("truth" in header) == truth and "attr_rf" in header
    back = MeasurementTable.from_csv(path)
    assert _bitwise_equal(t, back) and back == t


finite = st.floats(allow_nan=False, allow_infinity=False)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 2**40), finite, finite, finite), max_size=20))
def test_csv_round_trip_any_double(  # type: ignore[no-untyped-def]
    tmp_path_factory: pytest.TempPathFactory, rows
) -> None:
    s, t, a, e = (list(c) for c in zip(*rows, strict=True)) if rows else ([], [], [], [])
    table = MeasurementTable.from_arrays(s, t, a, e if rows else None, check_angle_unit=False)
    path = tmp_path_factory.mktemp("csv") / "t.csv"
    table.to_csv(path)
    assert _bitwise_equal(table, MeasurementTable.from_csv(path, check_angle_unit=False))


def test_from_csv_reports_bad_content(tmp_path: Path) -> None:
    path = tmp_path / "bad.csv"
    path.write_text("sensor,time,azimuth,elevation\n0,1.0,x,0.1\n")
    with pytest.raises(ValueError, match=r"^azimuth: line 2 has 'x', not a number"):
        MeasurementTable.from_csv(path)
    path.write_text("sensor,time,azimuth,elevation\n0,1.0,0.5,\n")
    with pytest.raises(ValueError, match=r"^elevation: line 2 has '', not a number \(file '.*bad.csv'\)"):
        MeasurementTable.from_csv(path)
    path.write_text("sensor,time,azimuth,azimuth\n0,1.0,0.5,0.1\n")
    with pytest.raises(ValueError, match=r"repeats a column name"):
        MeasurementTable.from_csv(path)
    with pytest.raises(ValueError, match=r"angle_unit"):
        MeasurementTable.from_csv(path, angle_unit="grad")  # type: ignore[arg-type]
    path.write_text("sensor,azimuth\n0,0.5\n")
    with pytest.raises(ValueError, match=r"^'.*bad.csv': missing required column 'time'"):
        MeasurementTable.from_csv(path)
    path.write_text("sensor,time,azimuth\n0,1.0\n")
    with pytest.raises(ValueError, match=r"^path: line 2 has 2 fields"):
        MeasurementTable.from_csv(path)


def test_from_csv_reads_other_tools_files(tmp_path: Path) -> None:
    """Spaces around names, a byte-order mark, degrees, extra columns: numeric ones become
    attributes, text ones are dropped with a warning that names them."""
    path = tmp_path / "scan.csv"
    path.write_text(
        "\ufeff sensor , time , azimuth , elevation , snr , label \n0, 1.0, 90, 10, 12.5, a\n1, 1.0, -45, 5, 9.0, b\n",
        encoding="utf-8",
    )
    with pytest.warns(UserWarning, match=r"ignoring non-numeric column\(s\) \['label'\]"):
        table = MeasurementTable.from_csv(path, angle_unit="deg")
    np.testing.assert_allclose(table.azimuth, np.radians([90.0, -45.0]))
    np.testing.assert_allclose(table.elevation, np.radians([10.0, 5.0]))
    assert table.sensor.tolist() == [0, 1] and table.attributes["snr"].tolist() == [12.5, 9.0]
    assert set(table.attributes) == {"snr"}
    # Written back, it reads again without the unit switch or the warning.
    table.to_csv(tmp_path / "back.csv")
    assert MeasurementTable.from_csv(tmp_path / "back.csv") == table


def test_pandas_round_trip() -> None:
    pytest.importorskip("pandas")
    t = _table(30)
    df = t.to_pandas()
    assert list(df.columns)[:5] == ["sensor", "time", "azimuth", "elevation", "truth"]
    assert _bitwise_equal(MeasurementTable.from_pandas(df), t)
    with pytest.raises(TypeError, match=r"^df: expected a pandas.DataFrame"):
        MeasurementTable.from_pandas({"sensor": [0]})


def test_pandas_missing_gives_install_hint(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "pandas", None)  # makes `import pandas` fail
    with pytest.raises(ImportError, match=r"pip install passive-assoc\[pandas\]"):
        _table().to_pandas()
    with pytest.raises(ImportError, match=r"pip install passive-assoc\[pandas\]"):
        MeasurementTable.from_pandas(object())


def test_select_and_sort() -> None:
    t = MeasurementTable.from_arrays(
        [0, 1, 0, 1],
        [3.0, 1.0, 1.0, 2.0],
        [0.1, 0.2, 0.3, 0.4],
        truth=[0, 1, 2, -1],
        attributes={"rf": [10.0, 20.0, 30.0, 40.0]},
    )
    sub = t.select([3, 0])
    assert sub.azimuth.tolist() == [0.4, 0.1] and sub.truth.tolist() == [-1, 0]
    assert sub.attributes["rf"].tolist() == [40.0, 10.0]
    assert t.select(np.array([True, False, False, True])) == sub.select([1, 0])
    assert len(t.select([])) == 0
    with pytest.raises(ValueError, match=r"^indices\[1\] = 4 is out of range"):
        t.select([0, 4])
    with pytest.raises(ValueError, match=r"^indices\[0\] = -1 is out of range"):
        t.select([-1])
    with pytest.raises(ValueError, match=r"^indices: boolean mask has shape \(2,\)"):
        t.select([True, False])
    s = t.sorted_by_time()
    assert s.time.tolist() == [1.0, 1.0, 2.0, 3.0]
    assert s.azimuth.tolist() == [0.2, 0.3, 0.4, 0.1]  # stable: the tie keeps row order
    assert t.time_order().tolist() == [1, 2, 3, 0]


def test_validate_against() -> None:
    net3 = SensorNetwork.spatial([[0, 0, 0], [1, 0, 0]], 0.01, 0.01)
    net2 = SensorNetwork.planar([[0, 0], [1, 0]], 0.01)
    t3 = MeasurementTable.from_arrays([0, 1, 1], [0.0, 0.0, 1.0], [0.1, 0.2, 0.3], [0.1] * 3)
    t3.validate_against(net3)
    with pytest.raises(ValueError, match=r"^measurements: the table is 3-D .* network is 2-D"):
        t3.validate_against(net2)
    t2 = MeasurementTable.from_arrays([0, 1], [0.0, 0.0], [0.1, 0.2])
    t2.validate_against(net2)
    with pytest.raises(ValueError, match=r"^measurements: the table is 2-D .* network is 3-D"):
        t2.validate_against(net3)
    bad = MeasurementTable.from_arrays([0, 1, 2, 5], [0.0] * 4, [0.1] * 4)
    with pytest.raises(ValueError, match=r"^sensor\[2\] = 2 \(row 2\) is not a sensor"):
        bad.validate_against(net2)
    MeasurementTable.from_arrays([], [], []).validate_against(net3)  # empty is fine
    with pytest.raises(TypeError, match=r"^sensors: expected a SensorNetwork"):
        t2.validate_against("net")  # type: ignore[arg-type]


def test_from_csv_accepts_a_byte_order_mark_and_padded_headers(tmp_path: Path) -> None:
    path = tmp_path / "excel.csv"
    path.write_text("sensor, time ,azimuth\n0,1.0,0.5\n1,2.0,0.25\n", encoding="utf-8-sig")
    table = MeasurementTable.from_csv(path)
    assert table.sensor.tolist() == [0, 1] and table.azimuth.tolist() == [0.5, 0.25]


def test_from_csv_turns_csv_module_errors_into_value_errors(tmp_path: Path) -> None:
    path = tmp_path / "long.csv"
    path.write_text("sensor,time,azimuth\n0,0," + "1" * 200_000 + "\n")
    with pytest.raises(ValueError, match=r"^path: .*long\.csv.* not a readable CSV file"):
        MeasurementTable.from_csv(path)


def test_parquet_round_trip_and_extra_columns(tmp_path: Path) -> None:
    pytest.importorskip("pyarrow")
    import pyarrow as pa_arrow
    import pyarrow.parquet as pq

    table = _table(40)
    table.to_parquet(tmp_path / "t.parquet")
    assert MeasurementTable.from_parquet(tmp_path / "t.parquet") == table
    pq.write_table(
        pa_arrow.table(
            {"sensor": [0, 1], "time": [0.0, 0.0], "azimuth": [90.0, 45.0], "snr": [3.0, 4.0], "tag": ["a", "b"]}
        ),
        tmp_path / "other.parquet",
    )
    with pytest.warns(UserWarning, match=r"\['tag'\]"):
        other = MeasurementTable.from_parquet(tmp_path / "other.parquet", angle_unit="deg")
    np.testing.assert_allclose(other.azimuth, np.radians([90.0, 45.0]))
    assert other.attributes["snr"].tolist() == [3.0, 4.0]


def test_angles_beyond_their_range_are_refused_as_degrees() -> None:
    """Elevations of 5–15 "rad" (degrees given as radians) gave 0 tracks: an error now, unless
    the caller says the values are meant."""
    with pytest.raises(ValueError, match=r"elevation\[0\] = 5\.0 rad is beyond ±π/2: were the angles given in degrees"):
        MeasurementTable.from_arrays([0, 1], [0.0, 0.0], [0.5, 0.7], [5.0, 15.0])
    with pytest.raises(ValueError, match=r"azimuth\[1\] = 200\.0 rad.*angle_unit='deg'.*check_angle_unit=False"):
        MeasurementTable.from_arrays([0, 1], [0.0, 0.0], [0.5, 200.0])
    kept = MeasurementTable.from_arrays([0, 1], [0.0, 0.0], [0.5, 200.0], check_angle_unit=False)
    assert kept.azimuth.tolist() == [0.5, 200.0] and kept.select([1]).azimuth.tolist() == [200.0]
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        MeasurementTable.from_arrays([0, 1], [0.0, 0.0], [-np.pi, 2 * np.pi], [np.pi / 2, -0.1])


@pytest.mark.parametrize(
    ("reader", "text", "column"),
    [
        ("sensors", "sensor,x,y,sigma_azimuth\n0,0,0,0.01\n{big},1,1,0.01\n", "sensor"),
        ("measurements", "sensor,time,azimuth\n0,0,0.1\n{big},0,0.2\n", "sensor"),
        ("tracks", "source,track,time,x,y\n0,0,0.0,1.0,2.0\n0,{big},0.0,1.0,2.0\n", "track"),
    ],
)
@pytest.mark.parametrize("big", [str(2**63), str(-(2**63) - 1), str(10**30)])
def test_an_integer_cell_beyond_int64_names_file_column_and_line(
    tmp_path: Path, reader: str, text: str, column: str, big: str
) -> None:
    """An integer cell beyond int64 raised a bare OverflowError from NumPy's cast: it is a bad
    cell like any other, named by column, line and file."""
    path = tmp_path / f"{reader}.csv"
    path.write_text(text.format(big=big))
    read = {"sensors": SensorNetwork.from_csv, "measurements": MeasurementTable.from_csv, "tracks": TrackTable.from_csv}
    with pytest.raises(ValueError, match=rf"^{column}: line 3 has '{big}', beyond the 64-bit integer range \(file "):
        read[reader](path)
