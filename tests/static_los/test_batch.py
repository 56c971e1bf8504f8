"""associate_scans equals a loop over associate_static, scan by scan, for every method; every
row ends in one target or is a false alarm; the thread count does not change the answer."""

from __future__ import annotations

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.simulation import static_scan


def stream(n_scans: int, n_targets: int = 6) -> tuple[pa.MeasurementTable, pa.SensorNetwork]:
    scans = [static_scan(seed, n_targets=n_targets).measurements.to_arrays() for seed in range(n_scans)]
    columns = {k: np.concatenate([s[k] for s in scans]) for k in scans[0]}
    columns["time"] = np.repeat(np.arange(n_scans, dtype=float) * 2.0, [len(s["time"]) for s in scans])
    return pa.MeasurementTable.from_columns(columns), static_scan(0, n_targets=n_targets).sensors


@pytest.mark.parametrize(
    "method,settings",
    [("intensity", {}), ("lagrangian", {}), ("exact", {"exact_backend": "branch_bound"}), ("lagrangian", {"pd": 0.9})],
)
def test_associate_scans_equals_the_loop(method: str, settings: dict[str, object]) -> None:
    table, sensors = stream(12)
    batch = pa.associate_scans(table, sensors, method=method, **settings)  # type: ignore[arg-type]
    assert batch.keys.tolist() == [2.0 * k for k in range(12)]
    assert len(batch.positions) == len(batch.target_scan) and len(batch.positions) > 12 * 3
    for k, key in enumerate(batch.keys):
        rows = np.flatnonzero(table.time == key)
        one = pa.associate_static(table.select(rows), sensors, method, **settings)  # type: ignore[arg-type]
        mine = np.flatnonzero(batch.target_scan == k)
        np.testing.assert_array_equal(batch.positions[mine], one.positions)
        expected = np.where(one.labels >= 0, one.labels + (mine[0] if len(mine) else 0), -1)
        np.testing.assert_array_equal(batch.labels[rows], expected)
        assert np.all(batch.scan[rows] == k)
    # Every row once: in a target of its own scan, or a false alarm.
    inside = batch.labels >= 0
    assert np.all(batch.target_scan[batch.labels[inside]] == batch.scan[inside])
    assert 0 < np.sum(~inside) < len(table)


def test_thread_count_and_scan_columns() -> None:
    table, sensors = stream(20)
    one = pa.associate_scans(table, sensors, method="lagrangian", n_threads=1)
    two = pa.associate_scans(table, sensors, method="lagrangian", n_threads=2)
    np.testing.assert_array_equal(one.labels, two.labels)
    np.testing.assert_array_equal(one.positions, two.positions)
    by_array = pa.associate_scans(table, sensors, scan=(table.time // 2).astype(int), method="lagrangian")
    np.testing.assert_array_equal(by_array.labels, one.labels)
    with pytest.raises(ValueError, match="scan: 'nope'"):
        pa.associate_scans(table, sensors, scan="nope")
    with pytest.raises(ValueError, match="one value per row"):
        pa.associate_scans(table, sensors, scan=[0, 1])
    with pytest.raises(ValueError, match="exact_backend"):
        pa.associate_scans(table, sensors, method="exact", exact_backend="highs")


def test_the_progress_bar_counts_scans_and_changes_nothing(capsys: pytest.CaptureFixture[str]) -> None:
    table, sensors = stream(12)
    shown = pa.associate_scans(table, sensors, method="lagrangian", progress=True)
    assert "scans:   0%" in capsys.readouterr().err
    quiet = pa.associate_scans(table, sensors, method="lagrangian", progress=False)
    assert capsys.readouterr().err == "" and np.array_equal(shown.labels, quiet.labels)

    reports: list[tuple[str, float]] = []
    pa.associate_scans(table, sensors, method="lagrangian", progress=lambda *r: reports.append(r))
    fractions = [f for stage, f in reports if stage == "scans"]
    assert len(fractions) == len(reports) >= 2  # the start and the end at least (rate-limited)
    assert fractions[0] == 0.0 and fractions[-1] == 1.0 and fractions == sorted(fractions)

    def failing(stage: str, fraction: float) -> None:
        raise RuntimeError(f"the bar broke at {stage}")

    with pytest.raises(RuntimeError, match="the bar broke at scans"):
        pa.associate_scans(table, sensors, method="lagrangian", progress=failing)
    # With a bar that does not fail, the call's own error still names the input.
    with pytest.raises(ValueError, match="candidate tuples"):
        pa.associate_scans(table, sensors, method="lagrangian", max_candidates=1, progress=True)


def test_exact_scans_take_the_path_of_associate_static() -> None:
    """``method="exact"`` with the default backend: a scan the branch-and-bound does not prove
    within its first 50 000 nodes goes to HiGHS in both calls. The batch once ran the
    branch-and-bound on to ``max_nodes``, and where the optimum ties the two picked different
    tuples of equal cost (8 of 1 000 scans; here the second, 189 476 nodes)."""
    scans = [static_scan(np.random.default_rng(seed), n_targets=7, ratio=5) for seed in range(3)]
    arrays = [s.measurements.to_arrays() for s in scans]
    columns = {k: np.concatenate([a[k] for a in arrays]) for k in arrays[0]}
    columns["time"] = np.repeat(np.arange(3.0), [len(a["time"]) for a in arrays])
    table, sensors = pa.MeasurementTable.from_columns(columns), scans[0].sensors
    batch = pa.associate_scans(table, sensors, method="exact", time_limit=None)
    for k, scan in enumerate(scans):
        one = pa.associate_static(scan.measurements, sensors, "exact", time_limit=None)
        mine = np.flatnonzero(batch.target_scan == k)
        rows = np.flatnonzero(table.time == k)
        np.testing.assert_array_equal(batch.positions[mine], one.positions)
        np.testing.assert_array_equal(batch.labels[rows], np.where(one.labels >= 0, one.labels + mine.min(), -1))
