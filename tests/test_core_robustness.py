"""No input may crash the interpreter or raise PanicException: every function of the compiled
core is called with each array argument replaced by a wrong dtype, an empty array, NaNs, a
wrong shape and out-of-range values. Only ValueError/TypeError (or a valid result) may come
back; PanicException derives from BaseException, so `except Exception` does not hide it."""

from __future__ import annotations

import contextlib
from typing import Any

import numpy as np
import pytest
from passive_assoc import _core

F64 = np.float64
I64 = np.int64


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


CASES: dict[str, tuple[Any, dict[str, Any], dict[str, Any]]] = {
    "fit_batch": (
        _core.fit_batch,
        {**_measurement_args(), "indices": np.arange(4, dtype=I64), "offsets": np.array([0, 4], I64)},
        dict(ndim=3, motion="cv"),
    ),
    "crlb": (
        _core.crlb,
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
        _core.closeness,
        {
            **_measurement_args(),
            "spread_azimuth": np.array([1e-2, 1e-2]),
            "spread_elevation": np.array([1e-2, 1e-2]),
            "states": np.ones((2, 6)),
        },
        dict(ndim=3, t0=0.0),
    ),
    "maximize_closeness": (
        _core.maximize_closeness,
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
        _core.initiate,
        {
            **_measurement_args(),
            "pairs": np.zeros((0, 2), I64),
            "spread_azimuth": np.array([1e-2, 1e-2]),
            "spread_elevation": np.array([1e-2, 1e-2]),
        },
        dict(
            ndim=3,
            t0=0.0,
            gate=5.0,
            n_detect=1,
            ray_gate=None,
            reject_behind=True,
            v_max=None,
            chi2_gate=None,
            one_per_scan=True,
            merge_tol=1.0,
            descent_max_iter=10,
            max_candidates=1000,
            n_threads=None,
        ),
    ),
    "enumerate_static": (
        _core.enumerate_static,
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
        dict(ndim=2, gate=6.6),
    ),
    "intensity_search": (
        _core.intensity_search,
        {
            "tuples": np.array([[1, 1, 1]], I64),
            "positions": np.zeros((1, 2)),
            "costs": np.array([-5.0]),
            "sizes": np.array([1, 1, 1], I64),
        },
        {},
    ),
    "assign_sd": (
        _core.assign_sd,
        {"tuples": np.array([[1, 1, 1]], I64), "costs": np.array([-5.0]), "sizes": np.array([1, 1, 1], I64)},
        {},
    ),
    "assign_2d": (_core.assign_2d, {"costs": np.ones((3, 4))}, {}),
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
        func(*args.values(), **kwargs)


@pytest.mark.parametrize("name", sorted(CASES))
def test_core_function_survives_mutated_inputs(name: str) -> None:
    func, args, kwargs = CASES[name]
    func(*args.values(), **kwargs)  # the unmutated call is valid
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
