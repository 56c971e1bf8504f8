"""Formation location with emitter attributes (METHODS §3): exactness on noiseless data, the
attribute gate's effect, agreement with the NumPy comparator, nothing lost, determinism."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.simulation import formation_scene, paper_formation_scene
from passive_assoc.simulation.formation import FormationScene


def _load_comparator() -> ModuleType:
    # benches/ is not a package; load the file by path (pytest runs with --import-mode=importlib).
    path = Path(__file__).resolve().parents[2] / "benches" / "formation_numpy.py"
    spec = importlib.util.spec_from_file_location("formation_numpy", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("formation_numpy", module)
    spec.loader.exec_module(module)
    return module


fnp = _load_comparator()


def _correct(result: pa.FormationResult, scene: FormationScene) -> np.ndarray:
    """Per baseline report: every sensor's chosen row is the target's true row."""
    truth = scene.true_tuples()
    target_of = scene.measurements.truth[result.baseline_rows]
    return np.array([t >= 0 and np.array_equal(result.rows[b], truth[t]) for b, t in enumerate(target_of)])


def _check_partition(result: pa.FormationResult, n_rows: int) -> None:
    """Every row is in exactly one group or in the clutter set, and each group's rows carry it."""
    labels = result.labels
    assert labels.shape == (n_rows,)
    assert len(result.clutter) + int((labels >= 0).sum()) == n_rows
    for b in np.flatnonzero(result.associated):
        chosen = result.rows[b][result.rows[b] >= 0]
        assert (result.times_chosen[chosen] >= 1).all()
    baseline_groups = labels[result.baseline_rows]
    assoc = result.associated
    assert (baseline_groups[assoc] == np.flatnonzero(assoc)).all()
    assert (baseline_groups[~assoc] == -1).all()


def test_noiseless_paper_scene_every_method_is_exact() -> None:
    scene = paper_formation_scene(0, sigma_deg=0.0)
    m, s, std = scene.measurements, scene.sensors, scene.attribute_std
    joint = pa.locate_formation(m, s, attribute_std=std)
    assert _correct(joint, scene).all()
    np.testing.assert_allclose(joint.positions, scene.targets, atol=1e-3)
    assert (joint.support[:, 1:] == 1.0).all()  # unperturbed attributes: every s_k = 1
    for method in ("lagrangian", "exact"):
        static = pa.associate_static(m, s, method, pd=0.99, attributes=None, attribute_std=std)
        assert sorted(map(tuple, static.rows)) == sorted(map(tuple, scene.true_tuples()))
    _check_partition(joint, len(m))


def test_azimuth_only_falls_for_the_exact_ghost_and_attributes_break_it() -> None:
    scene = paper_formation_scene(0, sigma_deg=0.0)
    azimuth_only = pa.locate_formation(scene.measurements, scene.sensors, attributes=[])
    correct = _correct(azimuth_only, scene)
    assert not (correct[0] and correct[2]), "T1/T3's ghost meets at one point with the truth"
    assert azimuth_only.diagnostics.attributes is False
    assert (azimuth_only.support[:, 1:] == 1.0).all()  # no attributes: no evidence either way
    assert azimuth_only.diagnostics.low_support == 0


def test_identical_attributes_make_the_joint_method_the_azimuth_only_one() -> None:
    scene = paper_formation_scene(3, sigma_deg=1.0)
    m = scene.measurements
    same = {name: np.full(len(m), 5.0) for name in m.attributes}
    table = pa.MeasurementTable.from_arrays(m.sensor, m.time, m.azimuth, attributes=same, truth=m.truth)
    joint = pa.locate_formation(table, scene.sensors, attribute_std=scene.attribute_std)
    azimuth = pa.locate_formation(table, scene.sensors, attributes=[])
    np.testing.assert_array_equal(joint.rows, azimuth.rows)
    np.testing.assert_array_equal(joint.radius, azimuth.radius)
    assert joint.diagnostics.low_support == 0 and joint.diagnostics.pairs == azimuth.diagnostics.pairs


@pytest.mark.parametrize("noise", ["paper", "realistic"])
def test_choices_equal_the_numpy_comparator(noise: str) -> None:
    for seed in range(15):
        scene = paper_formation_scene(seed, sigma_deg=1.5, noise=noise)  # type: ignore[arg-type]
        az, pos, attrs, std = fnp.per_sensor(scene)
        for gated in (True, False):
            ref_rows, ref_radius = fnp.locate_formation_numpy(az, pos, attrs if gated else None, std)
            ours = pa.locate_formation(
                scene.measurements,
                scene.sensors,
                attributes=None if gated else [],
                attribute_std=scene.attribute_std,
            )
            local = _local_indices(ours.rows, scene)
            np.testing.assert_array_equal(local, ref_rows, err_msg=f"seed {seed} gated {gated}")
            np.testing.assert_allclose(ours.radius, ref_radius, rtol=1e-9)


def test_large_scene_matches_the_comparator_and_the_thread_count() -> None:
    scene = formation_scene(4, n_sensors=4, n_emitters=40, sigma_deg=0.05, pd=0.9, clutter_per_sensor=3.0)
    az, pos, attrs, std = fnp.per_sensor(scene)
    ref_rows, _ = fnp.locate_formation_numpy(az, pos, attrs, std)
    runs = [
        pa.locate_formation(scene.measurements, scene.sensors, attribute_std=scene.attribute_std, n_threads=n)
        for n in (1, 2)
    ]
    np.testing.assert_array_equal(_local_indices(runs[0].rows, scene), ref_rows)
    np.testing.assert_array_equal(runs[0].rows, runs[1].rows)
    np.testing.assert_array_equal(runs[0].positions, runs[1].positions)
    _check_partition(runs[0], len(scene.measurements))
    assert _correct(runs[0], scene).mean() > 0.5


def test_one_to_one_uses_every_row_at_most_once() -> None:
    scene = formation_scene(5, n_sensors=4, n_emitters=30, sigma_deg=0.2, clutter_per_sensor=2.0)
    result = pa.locate_formation(scene.measurements, scene.sensors, attribute_std=scene.attribute_std, one_to_one=True)
    used = result.rows[result.rows >= 0]
    assert len(np.unique(used)) == len(used)
    assert result.times_chosen.max() <= 1
    _check_partition(result, len(scene.measurements))
    independent = pa.locate_formation(scene.measurements, scene.sensors, attribute_std=scene.attribute_std)
    assert independent.times_chosen.max() >= 2, "the scene should make independent baselines share"


def test_permuting_rows_permutes_the_answer() -> None:
    scene = paper_formation_scene(7, sigma_deg=1.0)
    m = scene.measurements
    order = np.random.default_rng(0).permutation(len(m))
    shuffled = m.select(order)
    a = pa.locate_formation(m, scene.sensors, attribute_std=scene.attribute_std)
    b = pa.locate_formation(shuffled, scene.sensors, attribute_std=scene.attribute_std)
    rows_a = {int(r[0]): tuple(r) for r in a.rows}
    rows_b = {int(order[r[0]]): tuple(order[x] if x >= 0 else -1 for x in r) for r in b.rows}
    assert rows_a == rows_b


def _local_indices(rows: np.ndarray, scene: FormationScene) -> np.ndarray:
    """Table rows → each sensor's report index (the comparator's numbering)."""
    sensor = scene.measurements.sensor
    local = np.full(len(sensor), -1, dtype=np.int64)
    for s in range(scene.sensors.n_sensors):
        mine = np.flatnonzero(sensor == s)
        local[mine] = np.arange(len(mine))
    return np.where(rows >= 0, local[np.maximum(rows, 0)], -1)


def test_per_sensor_and_per_report_stds_equal_the_per_attribute_ones() -> None:
    scene = paper_formation_scene(11, sigma_deg=1.5, noise="realistic")
    m, s, std = scene.measurements, scene.sensors, dict(scene.attribute_std)
    reference = pa.locate_formation(m, s, attribute_std=std)
    per_sensor = {name: [value] * s.n_sensors for name, value in std.items()}
    columns = {**m.attributes, **{f"{name}_std": np.full(len(m), value) for name, value in std.items()}}
    with_std_columns = pa.MeasurementTable.from_arrays(m.sensor, m.time, m.azimuth, attributes=columns)
    for result in (
        pa.locate_formation(m, s, attribute_std=per_sensor),
        pa.locate_formation(m, s, attribute_std=[std[name] for name in m.attributes]),
        pa.locate_formation(with_std_columns, s),  # stds from the `<name>_std` columns
    ):
        np.testing.assert_array_equal(result.rows, reference.rows)
        np.testing.assert_array_equal(result.support, reference.support)
    # A much larger RF std on sensor 1 changes its supports: per-sensor stds are really used.
    wider = {**per_sensor, "rf": [std["rf"], 1e4, std["rf"]]}
    changed = pa.locate_formation(m, s, attribute_std=wider)
    assert not np.array_equal(changed.support[:, 1], reference.support[:, 1], equal_nan=True)


@pytest.mark.parametrize("one_to_one", [False, True])
def test_an_absurd_azimuth_leaves_its_report_unassociated(one_to_one: bool) -> None:
    """An azimuth of 1e300 rad (refused at the table unless the caller keeps it) keeps no digits of its angle:
    the set holding it once came back ``associated`` with a NaN position and covariance. An
    associated report now always has a finite position; the others are as without the bad
    report, and every row ends in exactly one group or the clutter."""
    scene = paper_formation_scene(0, sigma_deg=0.0)
    columns = scene.measurements.to_arrays()
    columns["azimuth"] = columns["azimuth"].copy()
    columns["azimuth"][0] = 1e300  # the baseline sensor's first report
    with pytest.raises(ValueError, match="beyond ±2π"):
        pa.MeasurementTable.from_columns(columns)
    table = pa.MeasurementTable.from_columns(columns, check_angle_unit=False)
    result = pa.locate_formation(table, scene.sensors, attribute_std=scene.attribute_std, one_to_one=one_to_one)
    assert not result.associated[0]
    assert result.associated[1:].all()
    assert np.isfinite(result.positions[result.associated]).all()
    assert np.isfinite(result.covariances[result.associated]).all()
    assert np.isnan(result.positions[~result.associated]).all()
    assert len(result.clutter) + int((result.labels >= 0).sum()) == len(table)
    assert result.labels[0] == -1


def test_more_pairs_than_max_pairs_are_refused_before_any_work() -> None:
    """3 sensors × 16 000 reports once ran 90 CPU-s with no cap and no Ctrl-C check: the
    (baseline report, other report) pairs are capped (``max_pairs``, 5 × 10⁷ by default)."""
    rng = np.random.default_rng(0)
    big = pa.MeasurementTable.from_arrays(np.repeat([0, 1, 2], 16_000), np.zeros(48_000), rng.uniform(0.5, 2.6, 48_000))
    sensors = paper_formation_scene(0, sigma_deg=0.0).sensors
    with pytest.raises(ValueError, match=r"pairs: 512000000 exceeds the cap of 50000000; raise max_pairs"):
        pa.locate_formation(big, sensors, attributes=[])
    scene = paper_formation_scene(0, sigma_deg=0.0)
    assert pa.locate_formation(scene.measurements, scene.sensors, attributes=[], max_pairs=72).success
    with pytest.raises(ValueError, match=r"pairs: 72 exceeds the cap of 71"):
        pa.locate_formation(scene.measurements, scene.sensors, attributes=[], max_pairs=71)
    with pytest.raises(ValueError, match=r"^max_pairs: must be an integer >= 1"):
        pa.FormationLocator(max_pairs=0)


@pytest.mark.parametrize("one_to_one", [False, True])
def test_progress_reports_the_baseline_reports_and_can_stop_the_call(one_to_one: bool) -> None:
    scene = formation_scene(5, n_sensors=4, n_emitters=30, sigma_deg=0.2, clutter_per_sensor=2.0)
    locator = pa.FormationLocator(attribute_std=scene.attribute_std, one_to_one=one_to_one)
    reports: list[tuple[str, float]] = []
    watched = locator.locate(scene.measurements, scene.sensors, progress=lambda s, f: reports.append((s, f)))
    plain = locator.locate(scene.measurements, scene.sensors, progress=False)
    np.testing.assert_array_equal(watched.labels, plain.labels)
    assert reports[0] == ("baseline reports", 0.0) and ("baseline reports", 1.0) in reports
    assert (("one-to-one", 1.0) in reports) == one_to_one

    class Enough(Exception):
        pass

    def stop(stage: str, fraction: float) -> None:
        raise Enough(stage)

    with pytest.raises(Enough, match="baseline reports"):
        pa.locate_formation(scene.measurements, scene.sensors, attribute_std=scene.attribute_std, progress=stop)
    with pytest.raises(TypeError, match="progress"):
        locator.locate(scene.measurements, scene.sensors, progress="yes")  # type: ignore[arg-type]
