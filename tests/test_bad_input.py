"""Every exposed function rejects bad input with a ValueError/TypeError that names the
argument — never a crash or a PanicException (issue: foundation, "Bad input")."""

from __future__ import annotations

from collections.abc import Callable
from types import SimpleNamespace
from typing import Any

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc import _core

SENSORS = pa.SensorNetwork.spatial([[0, 0, 0], [20e3, 0, 0]], 5e-3, 5e-3)
TABLE = pa.MeasurementTable.from_arrays(
    [0, 1, 0, 1], [0.0, 5.0, 15.0, 20.0], [1.0, 2.0, 1.0, 2.0], [0.1, 0.1, 0.1, 0.1]
)


def _raw_fit_args() -> dict[str, Any]:
    return dict(
        sensor=np.array([0, 1, 0, 1], dtype=np.int64),
        time=np.array([0.0, 5.0, 15.0, 20.0]),
        azimuth=np.array([1.0, 2.0, 1.0, 2.0]),
        elevation=np.array([0.1, 0.1, 0.1, 0.1]),
        sensor_positions=SENSORS.positions.copy(),
        sigma_azimuth=np.array([5e-3, 5e-3]),
        sigma_elevation=np.array([5e-3, 5e-3]),
        indices=np.arange(4, dtype=np.int64),
        offsets=np.array([0, 4], dtype=np.int64),
    )


def _raw_fit(**change: Any) -> Any:
    """Call the compiled fit directly, with duck-typed table and network objects (the binding
    reads them by attribute), so that arrays a validated Python object would refuse reach it."""
    args = _raw_fit_args() | change
    measurements = SimpleNamespace(**{k: args.pop(k) for k in ("sensor", "time", "azimuth", "elevation")})
    sensors = SimpleNamespace(
        positions=args.pop("sensor_positions"),
        sigma_azimuth=args.pop("sigma_azimuth"),
        sigma_elevation=args.pop("sigma_elevation"),
        ndim=args.pop("ndim", 3),
    )
    settings = SimpleNamespace(
        motion=args.pop("motion", "cv"),
        t0=args.pop("t0", 0.0),
        max_iter=args.pop("max_iter", 50),
        xtol=args.pop("xtol", 1e-10),
        step_sigmas=args.pop("step_sigmas", 1e-6),
        max_halvings=args.pop("max_halvings", 30),
        n_threads=args.pop("n_threads", None),
    )
    indices, offsets, initial = args.pop("indices"), args.pop("offsets"), args.pop("initial", None)
    assert not args, f"unknown arguments {args}"
    return _core.fit_batch(measurements, sensors, indices, offsets, initial, settings)


RAW_CASES: list[tuple[str, dict[str, Any], type[Exception], str]] = [
    (
        "nan azimuth",
        dict(azimuth=np.array([1.0, np.nan, 1.0, 2.0])),
        ValueError,
        r"azimuth: non-finite value at index 1",
    ),
    ("inf time", dict(time=np.array([0.0, 5.0, np.inf, 1.0])), ValueError, r"time: non-finite value at index 2"),
    ("short time", dict(time=np.array([0.0, 5.0])), ValueError, r"time: has 2 rows, sensor has 4"),
    (
        "unknown sensor",
        dict(sensor=np.array([0, 1, 7, 1], dtype=np.int64)),
        ValueError,
        r"sensor: row 2 names sensor 7",
    ),
    ("negative sensor", dict(sensor=np.array([0, -1, 0, 1], dtype=np.int64)), ValueError, r"sensor: row 1"),
    ("zero std", dict(sigma_azimuth=np.array([5e-3, 0.0])), ValueError, r"sigma_azimuth: sensor 1 has std 0"),
    ("negative std", dict(sigma_elevation=np.array([-1.0, 5e-3])), ValueError, r"sigma_elevation: sensor 0"),
    ("coincident sensors", dict(sensor_positions=np.zeros((2, 3))), ValueError, r"sensors 0 and 1 coincide"),
    (
        "positions 2 columns",
        dict(sensor_positions=np.zeros((2, 2))),
        ValueError,
        r"sensor_positions: expected 3 columns",
    ),
    ("index out of range", dict(indices=np.array([0, 1, 2, 9], dtype=np.int64)), ValueError, r"indices: entry 3 is 9"),
    ("offsets wrong end", dict(offsets=np.array([0, 3], dtype=np.int64)), ValueError, r"offsets: last entry"),
    ("offsets decrease", dict(offsets=np.array([0, 3, 2, 4], dtype=np.int64)), ValueError, r"offsets: decreases"),
    (
        "too few measurements",
        dict(indices=np.array([0, 1], dtype=np.int64), offsets=np.array([0, 2], dtype=np.int64)),
        ValueError,
        r"problem 0 has 4 scalar measurements for 6 unknowns",
    ),
    ("bad motion", dict(motion="spline"), ValueError, r"motion: must be 'static' or 'cv'"),
    ("bad ndim", dict(ndim=4), ValueError, r"ndim: must be 2 or 3"),
    ("zero threads", dict(n_threads=0), ValueError, r"n_threads: must be at least 1"),
    ("absurd threads", dict(n_threads=10**7), ValueError, r"n_threads: 10000000 exceeds the maximum of 1024"),
    ("bad initial shape", dict(initial=np.zeros((1, 4))), ValueError, r"initial: expected shape \(1, 6\)"),
    ("nan initial", dict(initial=np.full((1, 6), np.nan)), ValueError, r"initial: non-finite"),
    ("zero max_iter", dict(max_iter=0), ValueError, r"max_iter: must be at least 1"),
    ("negative xtol", dict(xtol=-1.0), ValueError, r"xtol"),
    ("float32 azimuth", dict(azimuth=np.ones(4, dtype=np.float32)), TypeError, r"azimuth"),
    ("list instead of array", dict(time=[0.0, 1.0, 2.0, 3.0]), TypeError, r"time"),
    ("non-contiguous", dict(azimuth=np.ones(8)[::2]), ValueError, r"azimuth: array must be C-contiguous"),
]


@pytest.mark.parametrize("label,change,exc,message", RAW_CASES, ids=[c[0] for c in RAW_CASES])
def test_core_fit_batch_rejects(label: str, change: dict[str, Any], exc: type[Exception], message: str) -> None:
    with pytest.raises(exc, match=message):
        _raw_fit(**change)


def test_core_crlb_rejects() -> None:
    base = dict(
        sensor_positions=SENSORS.positions.copy(),
        sigma_azimuth=np.array([5e-3, 5e-3]),
        sigma_elevation=np.array([5e-3, 5e-3]),
        sensor_index=np.array([0, 1, 0, 1], dtype=np.int64),
        times=np.array([0.0, 5.0, 15.0, 20.0]),
        truth=np.array([1e3, 1e4, 1e3, 100.0, 0.0, 0.0]),
    )
    cases = [
        (dict(truth=np.zeros(4)), r"truth: expected 6 values"),
        (dict(times=np.array([0.0, 1.0])), r"times: has 2 entries"),
        (dict(sensor_index=np.array([0, 1, 0, 5], dtype=np.int64)), r"sensor_index: entry 3 is 5"),
        (dict(truth=np.array([0.0, 0.0, 1e3, 0, 0, 0])), r"vertical axis"),
        (
            dict(sensor_index=np.array([0, 1], dtype=np.int64), times=np.array([0.0, 1.0])),
            r"4 scalar measurements for 6",
        ),
    ]
    for change, message in cases:
        args = base | change
        with pytest.raises(ValueError, match=message):
            sensors = SimpleNamespace(
                positions=args["sensor_positions"],
                sigma_azimuth=args["sigma_azimuth"],
                sigma_elevation=args["sigma_elevation"],
                ndim=3,
            )
            _core.crlb(sensors, args["truth"], args["sensor_index"], args["times"], "cv", 0.0)


KF = pa.KalmanFilter(process_noise=1.0)
KF_POLAR = pa.KalmanFilter(measurement="polar", process_noise=1.0)
KF_T = np.array([0.0, 1.0, 2.0])
KF_Z = np.array([[0.0, 0.0], [10.0, 5.0], [20.0, 10.0]])


def _two_dense_sensors(n: int) -> tuple[pa.MeasurementTable, pa.SensorNetwork]:
    """n bearings per sensor, every pair of which meets: n² partial tuples."""
    rng = np.random.default_rng(0)
    sensors = pa.SensorNetwork.planar(np.array([[-1e4, 0.0], [1e4, 0.0]]), 1e-3)
    table = pa.MeasurementTable.from_arrays(np.repeat([0, 1], n), np.zeros(2 * n), rng.uniform(0.5, 2.5, 2 * n))
    return table, sensors


PUBLIC_CASES: list[tuple[str, Callable[[], Any], type[Exception], str]] = [
    (
        # unchecked, the gradient would be NaN
        "closeness at a 1e300 state",
        lambda: pa.closeness(TABLE, SENSORS, np.full((1, 6), 1e300)),
        ValueError,
        "state components must lie within",
    ),
    (
        # unchecked, the fit would be singular and NaN instead of refused
        "fit_ml t0 = 2**70",
        lambda: pa.fit_ml(TABLE, SENSORS, [np.arange(len(TABLE))], t0=2**70),
        ValueError,
        "t0",
    ),
    (
        # accepted, the covariances would be NaN
        "SensorNetwork sigma 1e-300",
        lambda: pa.SensorNetwork.planar(np.array([[0.0, 0.0], [1e4, 0.0]]), 1e-300),
        ValueError,
        "sigma_bearing",
    ),
    (
        "SensorNetwork sigma 1e300",
        lambda: pa.SensorNetwork.planar(np.array([[0.0, 0.0], [1e4, 0.0]]), 1e300),
        ValueError,
        "an angle std must lie in",
    ),
    (
        # accepted, the answer would cost 8.403 where the optimum is 0: 1e300 − 1e300 is lost to rounding
        "linear_assignment cost beyond ±1e150",
        lambda: pa.linear_assignment([[1e300, 11.07], [-2.667, -1e300]]),
        ValueError,
        "costs: entry 0 is 1e300; finite costs must lie within ±1e150",
    ),
    (
        # accepted, the sum would overflow to −inf and be reported optimal
        "assign_sd cost beyond ±1e150",
        lambda: pa.assign_sd([[1, 1, 0], [0, 1, 1]], [-1e308, -1e308], [1, 1, 1], method="exact"),
        ValueError,
        "costs: entry 0 is -1e308",
    ),
    (
        # 2 x 20 000 reports once aborted the interpreter allocating the pair list (15 GB);
        # the pairs are now decoded, never listed, and the cap stops the work.
        "enumerate_candidates cap on a dense scan",
        lambda: pa.enumerate_candidates(*_two_dense_sensors(3000), pd=0.9, max_candidates=1000),
        ValueError,
        "candidate tuples: 1001 exceeds the cap of 1000",
    ),
    (
        "fit_ml group longer than the table",
        lambda: pa.fit_ml(TABLE, SENSORS, [np.zeros(len(TABLE) + 1, dtype=np.int64)]),
        ValueError,
        "indices: problem 0 has",
    ),
    (
        "assign_sd all-zero tuple",
        lambda: pa.assign_sd([[0, 0, 0], [1, 1, 1]], [-3.0, -5.0], [1, 1, 1]),
        ValueError,
        "tuples: row 0 has no report",
    ),
    (
        "assign_sd max_nodes beyond int64",
        lambda: pa.assign_sd([[1, 1, 1]], [-5.0], [1, 1, 1], method="exact", max_nodes=2**63),
        ValueError,
        "max_nodes: 9223372036854775808 is out of the 64-bit integer range",
    ),
    (
        "assign_sd time_limit beyond Duration",
        lambda: pa.assign_sd([[1, 1, 1]], [-5.0], [1, 1, 1], method="exact", time_limit=1e20),
        ValueError,
        "time_limit",
    ),
    (
        "static_scan n_targets=0",
        lambda: pa.simulation.static_scan(1, n_targets=0),
        ValueError,
        "n_targets",
    ),
    (
        "static_scan pd=2",
        lambda: pa.simulation.static_scan(1, n_targets=3, pd=2),
        ValueError,
        "pd",
    ),
    (
        "fit_ml empty table",
        lambda: pa.fit_ml(TABLE.select(np.array([], dtype=np.int64)), SENSORS, [np.arange(0)]),
        ValueError,
        "measurements: the table is empty",
    ),
    (
        "fit_ml not a table",
        lambda: pa.fit_ml({"a": 1}, SENSORS, [np.arange(4)]),
        TypeError,
        "measurements: expected a MeasurementTable",
    ),
    ("fit_ml not sensors", lambda: pa.fit_ml(TABLE, np.zeros((2, 3)), [np.arange(4)]), TypeError, "sensors"),
    ("fit_ml string groups", lambda: pa.fit_ml(TABLE, SENSORS, [np.array(["a", "b"])]), TypeError, r"groups\[0\]"),
    ("fit_ml float groups", lambda: pa.fit_ml(TABLE, SENSORS, [np.array([0.5, 1.0])]), ValueError, r"groups\[0\]"),
    ("fit_ml no groups", lambda: pa.fit_ml(TABLE, SENSORS, []), ValueError, "groups: no problems"),
    ("fit_ml group too small", lambda: pa.fit_ml(TABLE, SENSORS, [np.arange(2)]), ValueError, "problem 0 has 4 scalar"),
    (
        "fit_ml initial shape",
        lambda: pa.fit_ml(TABLE, SENSORS, [np.arange(4)], initial=np.zeros((2, 6))),
        ValueError,
        "initial: expected shape",
    ),
    ("fit_ml nan t0", lambda: pa.fit_ml(TABLE, SENSORS, [np.arange(4)], t0=float("nan")), ValueError, "t0"),
    (
        "fit_ml 2-D table on 3-D network",
        lambda: pa.fit_ml(pa.MeasurementTable.from_arrays([0, 1], [0.0, 1.0], [0.1, 0.2]), SENSORS, [np.arange(2)]),
        ValueError,
        r"measurements: the table is 2-D \(elevation NaN\) but the sensor network is 3-D",
    ),
    ("crlb string truth", lambda: pa.crlb([0, 1, 0, 1], [0.0, 1, 2, 3], SENSORS, ["x"] * 6), TypeError, "truth"),
    (
        "crlb nan times",
        lambda: pa.crlb([0, 1, 0, 1], [0.0, np.nan, 2, 3], SENSORS, np.ones(6) * 1e3),
        ValueError,
        "times",
    ),
    (
        "sensors zero std",
        lambda: pa.SensorNetwork.spatial([[0, 0, 0], [1, 0, 0]], 0.0, 1e-3),
        ValueError,
        "sigma_azimuth",
    ),
    ("sensors coincident", lambda: pa.SensorNetwork.planar([[0, 0], [0, 0]], 1e-3), ValueError, "0 and 1"),
    ("sensors nan", lambda: pa.SensorNetwork.planar([[0, np.nan], [1, 0]], 1e-3), ValueError, "positions"),
    ("table mismatched", lambda: pa.MeasurementTable.from_arrays([0, 1], [0.0], [0.1, 0.2]), ValueError, "time"),
    ("table nan azimuth", lambda: pa.MeasurementTable.from_arrays([0], [0.0], [np.nan]), ValueError, "azimuth"),
    ("kalman negative q", lambda: pa.KalmanFilter(process_noise=-1.0), ValueError, "process_noise"),
    (
        "kalman unknown model",
        lambda: pa.KalmanFilter(measurement="bearing", process_noise=1.0),
        ValueError,
        "measurement",
    ),
    ("kalman string q", lambda: pa.KalmanFilter(process_noise="1"), TypeError, "process_noise"),
    ("kalman nan time", lambda: KF.filter([0.0, np.nan, 2.0], KF_Z, [np.arange(3)], noise=1.0), ValueError, "times"),
    ("kalman rows", lambda: KF.filter(KF_T, KF_Z[:2], [np.arange(2)], noise=1.0), ValueError, "measurements: has 2"),
    (
        "kalman four axes",
        lambda: KF.filter(KF_T, np.zeros((3, 4)), [np.arange(3)], noise=1.0),
        ValueError,
        "measurements",
    ),
    (
        "kalman string z",
        lambda: KF.filter(KF_T, [["a", "b"]] * 3, [np.arange(3)], noise=1.0),
        TypeError,
        "measurements",
    ),
    ("kalman noise shape", lambda: KF.filter(KF_T, KF_Z, [np.arange(3)], noise=np.ones(3)), ValueError, "noise"),
    ("kalman zero noise", lambda: KF.filter(KF_T, KF_Z, [np.arange(3)], noise=0.0), ValueError, "noise: row 0"),
    ("kalman no tracks", lambda: KF.filter(KF_T, KF_Z, [], noise=1.0), ValueError, "groups: no tracks"),
    ("kalman float groups", lambda: KF.filter(KF_T, KF_Z, [np.array([0.5, 1.0])], noise=1.0), ValueError, "groups"),
    ("kalman row twice", lambda: KF.filter(KF_T, KF_Z, [[0, 1], [1, 2]], noise=1.0), ValueError, "indices: row 1"),
    ("kalman row range", lambda: KF.filter(KF_T, KF_Z, [[0, 1, 7]], noise=1.0), ValueError, "indices: entry 2 is 7"),
    ("kalman unsorted", lambda: KF.filter(KF_T, KF_Z, [[0, 2, 1]], noise=1.0), ValueError, "times: track 0 goes back"),
    (
        "kalman sensors",
        lambda: KF.filter(KF_T, KF_Z, [[0, 1, 2]], noise=1.0, sensor_positions=[0, 0]),
        ValueError,
        "sensor_positions",
    ),
    (
        "kalman polar no sensors",
        lambda: KF_POLAR.filter(KF_T, KF_Z + 1, [[0, 1, 2]], noise=1.0),
        ValueError,
        "sensor_positions",
    ),
    (
        "kalman polar sensor shape",
        lambda: KF_POLAR.filter(KF_T, KF_Z + 1, [[0, 1, 2]], noise=1.0, sensor_positions=[0, 0, 0]),
        ValueError,
        "sensor_positions",
    ),
    (
        "kalman polar negative range",
        lambda: KF_POLAR.filter(KF_T, KF_Z - 1, [[0, 1, 2]], noise=1.0, sensor_positions=[0, 0]),
        ValueError,
        "measurements: row 0 has a negative range",
    ),
]


@pytest.mark.parametrize("label,call,exc,message", PUBLIC_CASES, ids=[c[0] for c in PUBLIC_CASES])
def test_public_functions_reject(label: str, call: Callable[[], Any], exc: type[Exception], message: str) -> None:
    with pytest.raises(exc, match=message):
        call()
