"""Tests of the argument helpers every entry point validates with (passive_assoc._validation)."""

from __future__ import annotations

import numpy as np
import pytest
from passive_assoc._validation import (
    as_float_array,
    as_float_scalar,
    as_int_array,
    require_finite,
    require_positive,
)


@pytest.mark.parametrize("value", ["abc", ["1.0", "2.0"], [1.0, None], np.array([1 + 2j]), [True, False]])
def test_as_float_array_rejects_non_real_types(value: object) -> None:
    with pytest.raises(TypeError, match=r"^x: expected real numbers"):
        as_float_array("x", value)


def test_as_float_array_shape_and_copy() -> None:
    src = np.arange(6, dtype=np.int32).reshape(2, 3)
    out = as_float_array("pos", src, shape=(None, 3))
    assert out.dtype == np.float64 and out.flags.c_contiguous
    out[0, 0] = 99.0
    assert src[0, 0] == 0  # a copy, never a view
    with pytest.raises(ValueError, match=r"^pos: expected shape \(\*, 2\), got \(2, 3\)"):
        as_float_array("pos", src, shape=(None, 2))
    with pytest.raises(ValueError, match=r"^pos: expected a 1-dimensional array"):
        as_float_array("pos", src, ndim=1)
    with pytest.raises(ValueError, match=r"^pos: cannot be converted"):
        as_float_array("pos", [[1.0, 2.0], [3.0]])
    with pytest.raises(TypeError, match=r"^pos: .*None"):
        as_float_array("pos", None)


def test_as_int_array_accepts_integral_floats_only() -> None:
    assert as_int_array("s", [0.0, 2.0]).tolist() == [0, 2]
    assert as_int_array("s", np.array([3], dtype=np.uint8)).dtype == np.int64
    with pytest.raises(ValueError, match=r"^s\[1\] = 1\.5 is not an integer"):
        as_int_array("s", [0.0, 1.5])
    with pytest.raises(ValueError, match=r"^s\[0\] = nan is not an integer"):
        as_int_array("s", [np.nan])
    with pytest.raises(TypeError, match=r"^s: expected integers"):
        as_int_array("s", ["0"])


def test_require_finite_and_positive_name_the_element() -> None:
    with pytest.raises(ValueError, match=r"^a\[1, 0\] = nan; all values must be finite"):
        require_finite("a", np.array([[1.0, 2.0], [np.nan, np.inf]]))
    with pytest.raises(ValueError, match=r"^b\[2\] = -1\.0; must be > 0"):
        require_positive("b", np.array([1.0, 2.0, -1.0, 0.0]))
    with pytest.raises(ValueError, match=r"^b\[0\] = nan; must be > 0"):
        require_positive("b", np.array([np.nan]))
    with pytest.raises(TypeError, match=r"^t: expected a scalar"):
        as_float_scalar("t", [1.0])
    assert as_float_scalar("t", np.float32(2.5)) == 2.5


@pytest.mark.parametrize("big", [2**70, -(2**70)])
def test_an_integer_beyond_int64_is_a_real_number(big: int) -> None:
    """``np.asarray(2**70)`` is an object array: it was refused as "expected real numbers, got
    an array of dtype object", though 2**70 is a real number."""
    assert as_float_array("x", big).item() == float(big)
    assert as_float_array("x", [1, big]).tolist() == [1.0, float(big)]
    assert as_float_scalar("x", big) == float(big)
    with pytest.raises(ValueError, match=r"^s\[1\] = -?1180591620717411303424 is out of the 64-bit integer range"):
        as_int_array("s", [0, big])
    with pytest.raises(ValueError, match=r"^x\[1\] = an integer of 401 digits is beyond the range of a float"):
        as_float_array("x", [0, 10**400])


def test_huge_integer_settings_are_refused_or_accepted_by_their_range() -> None:
    """``t0``, ``spread_factor``, ``false_alarm_density`` and ``pd`` given 2**70 (and
    10**400): each is checked against its range like any number, never by its Python type."""
    import passive_assoc as pa
    from passive_assoc.simulation import static_scan

    scan, fti = static_scan(1, n_targets=3), pa.paper_fti_scenario(1)
    state = fti.true_states[:1]
    assert pa.associate_static(scan.measurements, scan.sensors, false_alarm_density=2**70).success
    assert pa.associate_scans(scan.measurements, scan.sensors, false_alarm_density=2**70).success
    with pytest.raises(ValueError, match=r"^pd: sensor 0 has 1\.18\d*e\+21, must be in \(0\.0, 1\.0\)"):
        pa.associate_static(scan.measurements, scan.sensors, pd=2**70)
    with pytest.raises(ValueError, match=r"^false_alarm_density = an integer of 401 digits is beyond the range"):
        pa.associate_static(scan.measurements, scan.sensors, false_alarm_density=10**400)
    assert pa.closeness(fti.measurements, fti.sensors, state, spread_factor=2**70)[0].shape == (1,)
    with pytest.raises(ValueError, match=r"^spread_factor: an integer of 401 digits"):
        pa.closeness(fti.measurements, fti.sensors, state, spread_factor=10**400)
    for t0 in (2**70, 1e300, 10**400):
        with pytest.raises(ValueError, match=r"^t0: "):
            pa.closeness(fti.measurements, fti.sensors, state, t0=t0)
        with pytest.raises(ValueError, match=r"^t0: "):
            pa.maximize_closeness(fti.measurements, fti.sensors, state, np.eye(6)[None], t0=t0)
        with pytest.raises(ValueError, match=r"^t0: "):
            pa.fit_ml(fti.measurements, fti.sensors, fti.true_groups(), t0=t0)
