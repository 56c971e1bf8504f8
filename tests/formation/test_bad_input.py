"""Bad input to the formation method and the attribute gate: a ValueError/TypeError naming the
argument, never a panic or a silent fallback."""

from __future__ import annotations

from typing import Any

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.simulation import paper_formation_scene

SCENE = paper_formation_scene(0, sigma_deg=1.0)
STD = dict(SCENE.attribute_std)


def _locate(**settings: Any) -> pa.FormationResult:
    return pa.locate_formation(SCENE.measurements, SCENE.sensors, **{"attribute_std": STD, **settings})


@pytest.mark.parametrize(
    ("settings", "argument"),
    [
        ({"attributes": ["rf", "colour"]}, "attributes"),
        ({"attributes": "rf"}, "attributes"),
        ({"attribute_std": {"rf": -1.0, "prf": 5.0, "pw": 0.2, "asp": 0.2}}, "attribute_std"),
        ({"attribute_std": {"rf": 10.0}}, "attribute_std"),
        ({"attribute_std": [10.0, 5.0]}, "attribute_std"),
        ({"attribute_std": {"rf": [1.0, 2.0], "prf": 5.0, "pw": 0.2, "asp": 0.2}}, "attribute_std"),
        ({"attribute_std": None}, "attribute_std"),
        ({"eta": 0.0}, "eta"),
        ({"eta": 1.0}, "eta"),
        ({"eta": float("nan")}, "eta"),
        ({"combination": "dempster"}, "combination"),
        ({"baseline_sensor": 3}, "baseline_sensor"),
        ({"baseline_sensor": -1}, "baseline_sensor"),
        ({"reference": 0}, "reference"),
        ({"reference": 7}, "reference"),
        ({"cluster_radius": "3d"}, "cluster_radius"),
        ({"r_max": 0.0}, "r_max"),
        ({"region": (0.0, -1.0, 0.0, 1.0)}, "region"),
        ({"region": (0.0, 1.0)}, "region"),
        ({"n_threads": 0}, "n_threads"),
    ],
)
def test_bad_settings_name_the_argument(settings: dict[str, Any], argument: str) -> None:
    with pytest.raises((ValueError, TypeError), match=argument):
        _locate(**settings)


def test_non_finite_attributes_are_refused_at_the_table() -> None:
    m = SCENE.measurements
    bad = {name: np.array(col) for name, col in m.attributes.items()}
    bad["rf"][3] = np.nan
    with pytest.raises(ValueError, match="rf"):
        pa.MeasurementTable.from_arrays(m.sensor, m.time, m.azimuth, attributes=bad)


def test_too_few_sensors_and_3d_networks_are_refused() -> None:
    m = SCENE.measurements
    keep = m.sensor < 2
    two = pa.SensorNetwork(SCENE.sensors.positions[:2], SCENE.sensors.sigma_azimuth[:2])
    table = m.select(np.flatnonzero(keep))
    with pytest.raises(ValueError, match=r"sensors.*at least 3"):
        pa.locate_formation(table, two, attribute_std=STD)
    spatial = pa.SensorNetwork(
        np.column_stack([SCENE.sensors.positions[:, :2], np.zeros(3)]),
        SCENE.sensors.sigma_azimuth,
        np.full(3, 1e-3),
        ndim=3,
    )
    with pytest.raises(ValueError, match="3-D"):
        pa.locate_formation(m, spatial, attribute_std=STD)


def test_static_gate_checks_its_settings() -> None:
    m, s = SCENE.measurements, SCENE.sensors
    with pytest.raises(ValueError, match="eta"):
        pa.associate_static(m, s, "lagrangian", attributes=None, attribute_std=STD, eta=1.5)
    with pytest.raises(ValueError, match="attribute_std"):
        pa.associate_static(m, s, "lagrangian", attributes=["rf"])


def test_static_gate_cuts_candidates_and_keeps_the_truth() -> None:
    scene = paper_formation_scene(0, sigma_deg=0.0)
    m, s = scene.measurements, scene.sensors
    plain = pa.enumerate_candidates(m, s, pd=0.99)
    gated = pa.enumerate_candidates(m, s, pd=0.99, attributes=None, attribute_std=STD)
    assert gated.stages.attribute_pruned > 0 and plain.stages.attribute_pruned == 0
    assert len(gated.costs) < len(plain.costs)
    truth = {tuple(t) for t in scene.true_tuples()}
    assert truth <= {tuple(r) for r in gated.rows}
    # Every gated candidate's reports agree pairwise (m(assoc) ≥ η, computed independently),
    # and the candidates the gate removed include a pair that does not.
    names = list(STD)
    values = np.column_stack([m.attributes[n] for n in names])
    sigma = np.array([STD[n] for n in names])

    def mass(a: int, b: int) -> float:
        s_k = np.exp(-((values[a] - values[b]) ** 2) / (4 * sigma**2))
        return float(pa.evidence.simple_support_assoc(s_k))

    def agrees(rows: np.ndarray) -> bool:
        used = [int(r) for r in rows if r >= 0]
        return all(mass(a, b) >= 0.6 for i, a in enumerate(used) for b in used[i + 1 :])

    assert all(agrees(rows) for rows in gated.rows)
    kept = {tuple(r) for r in gated.rows}
    removed = [r for r in plain.rows if tuple(r) not in kept]
    assert removed and not any(agrees(r) for r in removed)


@pytest.mark.parametrize("method", ["formation", "lagrangian", "intensity"])
def test_an_attribute_std_key_naming_no_column_is_refused(method: str) -> None:
    """A typo in an ``attribute_std`` key ("rff") was silently dropped, with its std unused:
    refused, naming the key and the columns there are."""
    std = {**STD, "rff": 10.0}
    message = r"attribute_std: 'rff' names no attribute column; the table has \['rf', 'prf', 'pw', 'asp'\]"
    with pytest.raises(ValueError, match=message):
        if method == "formation":
            _locate(attribute_std=std)
        else:
            pa.associate_static(SCENE.measurements, SCENE.sensors, method, attributes=None, attribute_std=std)


@pytest.mark.parametrize("std", [1j, np.array([1.0 + 2j]), True])
def test_a_complex_or_boolean_std_is_a_type_error(std: object) -> None:
    """A complex std was cast to its real part with only NumPy's ComplexWarning (found by
    the fuzz test); True was read as 1."""
    with pytest.raises(TypeError, match=r"^attribute_std: std of 'rf' is not numeric"):
        _locate(attribute_std={**STD, "rf": std})


def test_an_integer_std_beyond_int64_is_a_number() -> None:
    assert _locate(attribute_std={**STD, "rf": 2**70}).success
    with pytest.raises(ValueError, match=r"^attribute_std = an integer of 401 digits is beyond the range of a float"):
        _locate(attribute_std={**STD, "rf": 10**400})
