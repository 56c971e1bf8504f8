"""No input may crash the interpreter or raise PanicException: every function of the compiled
core is called with each array argument replaced by a wrong dtype, an empty array, NaNs, a
wrong shape and out-of-range values. Only ValueError/TypeError (or a valid result) may come
back; PanicException derives from BaseException, so `except Exception` does not hide it."""

from __future__ import annotations

import contextlib
import subprocess
import sys
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest
from passive_assoc import _core
from passive_assoc._settings import AttributeEvidence, CoarseGateSettings

F64 = np.float64
I64 = np.int64


MEASUREMENT_KEYS = ("sensor", "time", "azimuth", "elevation", "sensor_position")
SENSOR_KEYS = {"sensor_positions": "positions", "sigma_azimuth": "sigma_azimuth", "sigma_elevation": "sigma_elevation"}


def _measurement_args() -> dict[str, Any]:
    return dict(
        sensor=np.array([0, 1, 0, 1], I64),
        time=np.array([0.0, 5.0, 15.0, 20.0]),
        azimuth=np.array([1.0, 2.0, 1.0, 2.0]),
        elevation=np.array([0.1, 0.1, 0.1, 0.1]),
        sensor_positions=np.array([[0.0, 0, 0], [2e4, 0, 0]]),
        sigma_azimuth=np.array([5e-3, 5e-3]),
        sigma_elevation=np.array([5e-3, 5e-3]),
    )


def _objects(args: dict[str, Any], ndim: Any) -> tuple[Any, Any, dict[str, Any]]:
    """Duck-typed table and network (the binding reads them by attribute) and the rest."""
    rest = dict(args)
    table = SimpleNamespace(**{k: rest.pop(k) for k in MEASUREMENT_KEYS if k in args})
    network = SimpleNamespace(**{attr: rest.pop(k) for k, attr in SENSOR_KEYS.items()}, ndim=ndim)
    return table, network, rest


def _fit(args: dict[str, Any], kw: dict[str, Any]) -> Any:
    table, network, rest = _objects(args, kw["ndim"])
    settings = SimpleNamespace(
        motion=kw["motion"], t0=0.0, max_iter=50, xtol=1e-10, step_sigmas=1e-6, max_halvings=30, n_threads=None
    )
    return _core.fit_batch(table, network, rest["indices"], rest["offsets"], None, settings)


def _crlb(args: dict[str, Any], kw: dict[str, Any]) -> Any:
    _, network, rest = _objects(args, kw["ndim"])
    return _core.crlb(network, rest["truth"], rest["sensor_index"], rest["times"], kw["motion"], 0.0)


def _crlb_reports(args: dict[str, Any], kw: dict[str, Any]) -> Any:
    """The CRLB with each report's sensor position and noise (a moving sensor)."""
    _, network, rest = _objects(args, kw["ndim"])
    reports = (rest["report_position"], rest["report_sigma_azimuth"], rest["report_sigma_elevation"])
    return _core.crlb(network, rest["truth"], rest["sensor_index"], rest["times"], kw["motion"], 0.0, *reports)


def _closeness(args: dict[str, Any], kw: dict[str, Any]) -> Any:
    table, network, rest = _objects(args, kw["ndim"])
    spreads = (rest["spread_azimuth"], rest["spread_elevation"])
    return _core.closeness(table, network, spreads, rest["states"], kw["t0"], None)


def _maximize(args: dict[str, Any], kw: dict[str, Any]) -> Any:
    table, network, rest = _objects(args, kw["ndim"])
    spreads = (rest["spread_azimuth"], rest["spread_elevation"])
    settings = SimpleNamespace(t0=kw["t0"], scaling="whitened", max_iter=100, n_threads=None)
    return _core.maximize_closeness(table, network, spreads, rest["starts"], rest["covariances"], settings)


def _initiate(args: dict[str, Any], kw: dict[str, Any]) -> Any:
    kw = dict(kw)
    table, network, rest = _objects(args, kw.pop("ndim"))
    t0 = kw.pop("t0")
    settings = SimpleNamespace(
        **kw,
        candidates="auto",
        prefit_gates=True,
        sweep=True,
        untangle=True,
        on_limit="warn",
        detection_order="membership",
        descent_scaling="whitened",
        refine_passes=2,
        candidate_scans=4,
        support_gate=True,
        track_test=1e-6,
        gate_pd=None,
    )
    spreads = (rest["spread_azimuth"], rest["spread_elevation"])
    return _core.initiate(table, network, rest["pairs"], spreads, t0, settings)


def _enumerate(args: dict[str, Any], kw: dict[str, Any]) -> Any:
    table, network, rest = _objects({**args, "time": np.zeros(len(args["sensor"]))}, kw["ndim"])
    settings = SimpleNamespace(gate_sigmas=kw["gate_sigmas"], min_intensity=2, max_candidates=1_000_000, n_threads=None)
    return _core.enumerate_static(table, network, rest["pd"], rest["false_alarm_density"], settings)


def _intensity(args: dict[str, Any], kw: dict[str, Any]) -> Any:
    settings = SimpleNamespace(vote_fraction=0.5, valid_airspace=True, max_chains=None, n_threads=None)
    return _core.intensity_search(args["tuples"], args["positions"], args["costs"], args["sizes"], settings)


def _assign_sd(args: dict[str, Any], kw: dict[str, Any]) -> Any:
    settings = _sd_settings(time_limit=10.0)
    return _core.assign_sd(args["tuples"], args["costs"], args["sizes"], "lagrangian", settings)


def _sd_settings(time_limit: float) -> SimpleNamespace:
    """What the binding reads of the S-D solvers' settings."""
    return SimpleNamespace(
        max_iter=200,
        gap_tol=1e-3,
        max_nodes=10_000_000,
        time_limit=time_limit,
        warm_start="auto",
        sensor_order="auto",
        polish=False,
    )


def _kalman(args: dict[str, Any], kw: dict[str, Any]) -> Any:
    settings = SimpleNamespace(**kw, init="differencing", init_velocity_std=500.0, init_acceleration_std=50.0)
    groups = (args["indices"], args["offsets"])
    return _core.kalman_filter(
        args["times"], args["measurements"], groups, args["noise"], args["sensor_positions"], settings
    )


def _coarse_gate(args: dict[str, Any], kw: dict[str, Any]) -> Any:
    settings = CoarseGateSettings(**kw)
    radar = (args["radar_coefficients"], args["radar_variances"])
    esm = (args["esm_coefficients"], args["esm_variances"])
    return _core.wavelet_coarse_gate(args["operator"], radar, esm, settings)


def _locate_formation(args: dict[str, Any], kw: dict[str, Any]) -> Any:
    kw = dict(kw)
    table, network, rest = _objects({**args, "time": np.zeros(len(args["sensor"]))}, 2)
    evidence = AttributeEvidence(rest["attributes"], rest["attribute_std"], kw.pop("eta"), kw.pop("combination"))
    return _core.locate_formation(table, network, evidence, SimpleNamespace(**kw))


def _enumerate_gated(args: dict[str, Any], kw: dict[str, Any]) -> Any:
    table, network, rest = _objects({**args, "time": np.zeros(len(args["sensor"]))}, 2)
    evidence = AttributeEvidence(rest["attributes"], rest["attribute_std"], kw["eta"], kw["combination"])
    settings = SimpleNamespace(gate_sigmas=2.57, min_intensity=2, max_candidates=1_000_000, n_threads=None)
    return _core.enumerate_static(table, network, rest["pd"], rest["false_alarm_density"], settings, evidence)


def _formation_args() -> dict[str, Any]:
    return {
        "sensor": np.array([0, 0, 1, 1, 2, 2], I64),
        "azimuth": np.array([1.2, 1.4, 1.5, 1.6, 1.9, 2.0]),
        "elevation": np.full(6, np.nan),
        "sensor_positions": np.array([[-1e4, 0, 0], [0, -5e3, 0], [1e4, 0, 0.0]]),
        "sigma_azimuth": np.full(3, 1e-3),
        "sigma_elevation": np.full(3, 1e-3),
        # (K, N): the attribute columns stacked; one std per attribute (K, 1).
        "attributes": np.array([[1.0, 2.0, 1.1, 2.1, 1.0, 2.0], [5.0, 6.0, 5.0, 6.0, 5.1, 6.1]]),
        "attribute_std": np.full((2, 1), 0.1),
    }


CASES: dict[str, tuple[Any, dict[str, Any], dict[str, Any]]] = {
    "locate_formation": (
        _locate_formation,
        _formation_args(),
        dict(
            eta=0.6,
            combination="simple",
            baseline_sensor=0,
            reference="smallest",
            cluster_radius="2d",
            one_to_one=True,
            r_max=2e5,
            region=(-1e5, 1e5, -1e5, 1e5),
            in_front=False,
            max_pairs=1000,
            n_threads=None,
        ),
    ),
    "enumerate_static_gated": (
        _enumerate_gated,
        {**_formation_args(), "pd": np.full(3, 0.9), "false_alarm_density": np.full(3, 1.0)},
        dict(eta=0.6, combination="two_outcome"),
    ),
    "fit_batch": (
        _fit,
        {**_measurement_args(), "indices": np.arange(4, dtype=I64), "offsets": np.array([0, 4], I64)},
        dict(ndim=3, motion="cv"),
    ),
    "fit_batch_moving": (
        _fit,
        {
            **_measurement_args(),
            "sensor_position": np.array([[0.0, 0, 0], [2e4, 10, 0], [50.0, 0, 0], [np.nan] * 3]),
            "indices": np.arange(4, dtype=I64),
            "offsets": np.array([0, 4], I64),
        },
        dict(ndim=3, motion="cv"),
    ),
    "crlb_reports": (
        _crlb_reports,
        dict(
            sensor_positions=np.array([[0.0, 0, 0], [2e4, 0, 0]]),
            sigma_azimuth=np.array([5e-3, 5e-3]),
            sigma_elevation=np.array([5e-3, 5e-3]),
            sensor_index=np.array([0, 1, 0, 1], I64),
            times=np.array([0.0, 5, 15, 20]),
            truth=np.array([1e3, 1e4, 1e3, 100, 0, 0.0]),
            report_position=np.array([[0.0, 0, 0], [2e4, 10, 0], [np.nan] * 3, [2e4, 500, 0]]),
            report_sigma_azimuth=np.array([1e-3, np.nan, 2e-3, 3e-3]),
            report_sigma_elevation=np.array([1e-3, 1e-3, np.nan, 3e-3]),
        ),
        dict(ndim=3, motion="cv"),
    ),
    "crlb": (
        _crlb,
        dict(
            sensor_positions=np.array([[0.0, 0, 0], [2e4, 0, 0]]),
            sigma_azimuth=np.array([5e-3, 5e-3]),
            sigma_elevation=np.array([5e-3, 5e-3]),
            sensor_index=np.array([0, 1, 0, 1], I64),
            times=np.array([0.0, 5, 15, 20]),
            truth=np.array([1e3, 1e4, 1e3, 100, 0, 0.0]),
        ),
        dict(ndim=3, motion="cv"),
    ),
    "closeness": (
        _closeness,
        {
            **_measurement_args(),
            "spread_azimuth": np.array([1e-2, 1e-2]),
            "spread_elevation": np.array([1e-2, 1e-2]),
            "states": np.ones((2, 6)),
        },
        dict(ndim=3, t0=0.0),
    ),
    "maximize_closeness": (
        _maximize,
        {
            **_measurement_args(),
            "spread_azimuth": np.array([1e-2, 1e-2]),
            "spread_elevation": np.array([1e-2, 1e-2]),
            "starts": np.ones((1, 6)) * 1e3,
            "covariances": np.eye(6)[None] * 100,
        },
        dict(ndim=3, t0=0.0),
    ),
    "initiate": (
        _initiate,
        {
            **_measurement_args(),
            "pairs": np.zeros((0, 2), I64),
            "spread_azimuth": np.array([1e-2, 1e-2]),
            "spread_elevation": np.array([1e-2, 1e-2]),
        },
        dict(
            ndim=3,
            t0=0.0,
            gate_sigmas=5.0,
            n_detect=1,
            ray_gate_sigmas=None,
            reject_behind=True,
            v_max=None,
            chi2_gate=None,
            one_per_scan=True,
            merge_tol=1.0,
            descent_max_iter=10,
            max_candidates=1000,
            search_stage=8192,
            n_threads=None,
        ),
    ),
    "enumerate_static": (
        _enumerate,
        {
            "sensor": np.array([0, 1, 2], I64),
            "azimuth": np.array([1.0, 1.5, 2.0]),
            "elevation": np.zeros(3),
            "sensor_positions": np.array([[-1e4, 0, 0], [0, -5e3, 0], [1e4, 0, 0.0]]),
            "sigma_azimuth": np.full(3, 1e-3),
            "sigma_elevation": np.full(3, 1e-3),
            "pd": np.full(3, 0.9),
            "false_alarm_density": np.full(3, 1.0),
        },
        dict(ndim=2, gate_sigmas=2.57),
    ),
    "intensity_search": (
        _intensity,
        {
            "tuples": np.array([[1, 1, 1]], I64),
            "positions": np.zeros((1, 2)),
            "costs": np.array([-5.0]),
            "sizes": np.array([1, 1, 1], I64),
        },
        {},
    ),
    "assign_sd": (
        _assign_sd,
        {"tuples": np.array([[1, 1, 1]], I64), "costs": np.array([-5.0]), "sizes": np.array([1, 1, 1], I64)},
        {},
    ),
    "assign_2d": (lambda args, kw: _core.assign_2d(args["costs"]), {"costs": np.ones((3, 4))}, {}),
    "kalman_filter": (
        _kalman,
        {
            "times": np.array([0.0, 1.0, 2.0, 0.5, 1.5]),
            "measurements": np.array([[1e3, 0.1], [1.1e3, 0.1], [1.2e3, 0.1], [5e2, -3.1], [5e2, 3.1]]),
            "indices": np.array([0, 1, 2, 3, 4], I64),
            "offsets": np.array([0, 3, 5], I64),
            "noise": np.array([[10.0, 1e-3]] * 5),
            "sensor_positions": np.zeros((5, 2)),
        },
        dict(motion="cv", measurement="polar", process_noise=1.0, n_threads=None),
    ),
    "wavelet_coarse_gate": (
        _coarse_gate,
        {
            "operator": np.array([[0.5, 0.5, 0.0], [0.0, 0.5, 0.5]]),
            "radar_coefficients": np.array([[[1.0, 2.0]], [[0.0, -1.0]]]),
            "radar_variances": np.full((2, 1, 3), 0.5),
            "esm_coefficients": np.array([[[1.0, 2.5]], [[3.0, 0.0]], [[0.0, 0.0]]]),
            "esm_variances": np.full((3, 1, 3), 2.0),
        },
        dict(threshold=9.21, whitened=True, n_threads=None),
    ),
}


def _mutations(value: np.ndarray) -> list[Any]:
    out: list[Any] = [
        value.astype(np.float32 if value.dtype == F64 else np.int32),
        value.reshape(-1)[:0].reshape((0, *value.shape[1:])),
        np.zeros((*value.shape[:-1], value.shape[-1] + 1), value.dtype) if value.ndim else value,
        "text",
        None,
    ]
    if value.dtype == F64:
        out += [np.full_like(value, np.nan), np.full_like(value, np.inf), -value, np.full_like(value, 1e300)]
    else:
        out += [value - 10, value + 10**9, np.full_like(value, np.iinfo(I64).max)]
    if value.ndim == 2:
        out.append(value.T.copy())
        out.append(np.asfortranarray(np.hstack([value, value]))[:, ::2])
    return out


def _call(func: Any, args: dict[str, Any], kwargs: dict[str, Any]) -> None:
    with contextlib.suppress(ValueError, TypeError):
        func(args, kwargs)


@pytest.mark.parametrize("name", sorted(CASES))
def test_core_function_survives_mutated_inputs(name: str) -> None:
    func, args, kwargs = CASES[name]
    func(args, kwargs)  # the unmutated call is valid
    for key, value in args.items():
        for bad in _mutations(value):
            _call(func, {**args, key: bad}, kwargs)


@pytest.mark.parametrize("name", sorted(CASES))
def test_core_function_survives_bad_keywords(name: str) -> None:
    func, args, kwargs = CASES[name]
    for key, value in kwargs.items():
        for bad in (-1, 0, 10**12, float("nan"), "text", None):
            if type(bad) is type(value) and bad == value:
                continue
            _call(func, args, {**kwargs, key: bad})


def test_fortran_ordered_arrays_are_refused_not_read_transposed() -> None:
    """rust-numpy's as_slice accepts Fortran order; the bindings must not read it as row-major."""
    costs = np.array([[1.0, 11.0, 5.0], [-3.0, 2.0, 7.0]])
    with pytest.raises(ValueError, match=r"costs.*C-contiguous"):
        _core.assign_2d(np.asfortranarray(costs))
    _rows, cols, total = _core.assign_2d(costs)
    assert total == 2.0 and list(cols) == [2, 0]  # 5 + (−3), the optimum by enumeration


def test_a_huge_time_limit_is_a_value_error_not_a_panic() -> None:
    settings = _sd_settings(time_limit=1e20)
    with pytest.raises(ValueError, match="time_limit"):
        _core.assign_sd(np.array([[1, 1, 1]], I64), np.array([-5.0]), np.array([1, 1, 1], I64), "exact", settings)


_OOM_SCRIPT = """
import resource
import numpy as np
import passive_assoc as pa

resource.setrlimit(resource.RLIMIT_AS, (3 << 29, 3 << 29))  # 1.5 GB of address space
rng = np.random.default_rng(0)
sensor = np.repeat([0, 1, 0, 1], 500)
time = np.repeat([0.0, 0.0, 30.0, 30.0], 500)
table = pa.MeasurementTable.from_arrays(sensor, time, rng.uniform(0.3, 2.8, 2000))
sensors = pa.SensorNetwork.planar(np.array([[-2e4, 0.0], [2e4, 0.0]]), 2e-3)
try:
    pa.FuzzyTrackInitiator(v_max=None, max_candidates=10**9, ray_gate_sigmas=None).initiate(table, sensors)
except MemoryError as err:
    print("MemoryError", err)
"""


@pytest.mark.skipif(sys.platform != "linux", reason="RLIMIT_AS is how the test bounds memory")
def test_candidates_outgrowing_memory_raise_memory_error_not_abort() -> None:
    """500 clutter bearings per sensor and scan, no v_max, a cap of 10⁹: the candidates once
    grew until an allocation failed and the interpreter aborted."""
    done = subprocess.run([sys.executable, "-c", _OOM_SCRIPT], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.startswith("MemoryError fitted candidates: could not allocate"), done.stdout


_DECLARED_SIZES_SCRIPT = """
import resource
import numpy as np
import passive_assoc as pa

resource.setrlimit(resource.RLIMIT_AS, (3 << 29, 3 << 29))  # 1.5 GB of address space
tuples = np.zeros((3, 40), dtype=np.int64)
tuples[0, :2] = 1
tuples[1, 2:4] = 1
tuples[2, [0, 5]] = [2, 1]
for method in ("lagrangian", "exact"):
    print(pa.assign_sd(tuples, [-1.0, -2.0, -3.0], [10**7] * 40, method=method).primal_cost)
"""


@pytest.mark.skipif(sys.platform != "linux", reason="RLIMIT_AS is how the test bounds memory")
def test_declared_sizes_do_not_size_the_solvers_memory() -> None:
    """S = 40 sensors declaring 10⁷ reports each for three tuples once needed 3.2 GB of
    multipliers; the solvers now size them by the reports the tuples use."""
    done = subprocess.run([sys.executable, "-c", _DECLARED_SIZES_SCRIPT], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.split() == ["-6.0", "-6.0"], done.stdout
