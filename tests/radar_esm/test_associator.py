"""Radar/ESM association (METHODS §5) through the public API: the wavelet-fuzzy associator and
its two baselines lose no track, ignore ids, pair noiseless targets correctly, work in 1-D,
2-D and 3-D and against a passive track, and refuse bad input naming the argument."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.experiments.wavelet_passive import demo_tracks
from passive_assoc.experiments.wavelet_runs import PROCESS_NOISE, score
from passive_assoc.radar_esm import RadarEsmAssociation, coarse_gate, filter_reports
from passive_assoc.radar_esm.fuzzy import _heading, membership
from passive_assoc.radar_esm.scan_gate import gate_diagonal
from passive_assoc.simulation import paper_wavelet_scenario

METHODS: dict[str, Callable[[], pa.TrackAssociator]] = {
    "wavelet": pa.WaveletFuzzyAssociator,
    "wavelet_cross_time": lambda: pa.WaveletFuzzyAssociator(process_noise=PROCESS_NOISE),
    "wavelet_per_scan": lambda: pa.WaveletFuzzyAssociator(process_noise=None),
    "wavelet_paper": pa.WaveletFuzzyAssociator.paper,
    "combined": pa.radar_esm.WaveletChi2Associator,
    "nearest": pa.NearestNeighbourAssociator,
    "chi2": pa.Chi2TrackAssociator,
}


def sensor_tracks(seed: int, n_clutter: int = 0, **kwargs: float) -> tuple[pa.TrackTable, pa.TrackTable, np.ndarray]:
    """The paper scenario's radar and ESM tracks (CA Kalman filters), and the scan times."""
    scenario = paper_wavelet_scenario(seed, n_clutter=n_clutter, **kwargs)  # type: ignore[arg-type]
    tracks = filter_reports(scenario.measurements, PROCESS_NOISE)
    return tracks.of(0), tracks.of(1), scenario.scan_times


def keys(result: RadarEsmAssociation) -> list[tuple[float, int, int]]:
    p = result.pairs
    return sorted(zip(p.time.tolist(), p.local_track.tolist(), p.system_track.tolist(), strict=True))


@pytest.mark.parametrize("method", METHODS)
def test_every_track_of_every_scan_is_paired_or_unpaired(method: str) -> None:
    radar, esm, _ = sensor_tracks(1, n_clutter=2)
    result = METHODS[method]().associate(local=esm, system=radar)
    assert len(result.pairs) > 0.5 * len(esm), "most tracks are paired: the check is not vacuous"
    assert len(result.unpaired_local) > 0 or len(result.unpaired_system) > 0 or method == "nearest"
    p, u, v = result.pairs, result.unpaired_local, result.unpaired_system
    esm_seen = list(zip(p.time.tolist(), p.local_track.tolist(), strict=True)) + list(
        zip(u.time.tolist(), u.track.tolist(), strict=True)
    )
    radar_seen = list(zip(p.time.tolist(), p.system_track.tolist(), strict=True)) + list(
        zip(v.time.tolist(), v.track.tolist(), strict=True)
    )
    assert sorted(esm_seen) == sorted(zip(esm.time.tolist(), esm.track.tolist(), strict=True))
    assert sorted(radar_seen) == sorted(zip(radar.time.tolist(), radar.track.tolist(), strict=True))
    assert set(p.source.tolist()) == {1} and set(u.source.tolist()) <= {1}


@pytest.mark.parametrize("method", METHODS)
def test_track_ids_do_not_matter(method: str) -> None:
    radar, esm, _ = sensor_tracks(2, n_clutter=1)
    rng = np.random.default_rng(0)
    new_r, new_e = 500 + rng.permutation(100), 900 + rng.permutation(100)

    def relabelled(table: pa.TrackTable, new: np.ndarray) -> pa.TrackTable:
        columns = {k: getattr(table, k) for k in ("source", "time", "position", "velocity", "acceleration")}
        return pa.TrackTable.from_arrays(
            track=new[table.track], covariance=table.covariance, truth=table.truth, sort=True, **columns
        )

    a = METHODS[method]().associate(local=esm, system=radar)
    b = METHODS[method]().associate(local=relabelled(esm, new_e), system=relabelled(radar, new_r))
    mapped = sorted(
        zip(
            a.pairs.time.tolist(),
            new_e[a.pairs.local_track].tolist(),
            new_r[a.pairs.system_track].tolist(),
            strict=True,
        )
    )
    assert len(mapped) > 0 and mapped == keys(b)


@pytest.mark.parametrize("method", METHODS)
def test_noiseless_distinct_targets_are_all_paired_correctly(method: str) -> None:
    """Exact positions, filtered with a nominal 1 m noise: every target, every scan (the
    filter starts from a prior at the first report; from the first three, scans 1-2 have no
    track)."""
    scenario = paper_wavelet_scenario(3, noise_variance=0.0)
    tracks = filter_reports(scenario.measurements, PROCESS_NOISE, noise=1.0)
    radar, esm = tracks.of(0), tracks.of(1)
    correct, _ = score(METHODS[method]().associate(local=esm, system=radar), radar, esm, scenario.scan_times)
    assert correct.tolist() == [1.0] * 30
    late = filter_reports(scenario.measurements, PROCESS_NOISE, noise=1.0, init="differencing")
    correct, _ = score(
        METHODS[method]().associate(local=late.of(1), system=late.of(0)), late.of(0), late.of(1), scenario.scan_times
    )
    assert np.isnan(correct[:2]).all() and correct[2:].tolist() == [1.0] * 28


@pytest.mark.parametrize("process_noise", [None, PROCESS_NOISE])
def test_two_and_three_dimensional_tracks(process_noise: float | None) -> None:
    """Far above chance (0.1) in 2-D and in 3-D, with Σ per scan and with the cross-time
    covariance."""
    radar, esm, times = sensor_tracks(4, ndim=2)
    associator = pa.WaveletFuzzyAssociator(process_noise=process_noise)
    correct, _ = score(associator.associate(local=esm, system=radar), radar, esm, times)
    assert np.nanmean(correct[5:]) > 0.5
    # 3-D: the same tracks at a common altitude of 5 km, with a z variance like x's.
    lifted = []
    for table in (radar, esm):
        assert table.covariance is not None and table.velocity is not None and table.acceleration is not None
        pad = np.zeros((len(table), 1))
        cov = np.zeros((len(table), 9, 9))
        old = [0, 1, 2, 3, 4, 5]  # x, y, vx, vy, ax, ay → into x, y, _, vx, vy, _, ax, ay, _
        new = [0, 1, 3, 4, 6, 7]
        cov[np.ix_(np.arange(len(table)), new, new)] = table.covariance[np.ix_(np.arange(len(table)), old, old)]
        # z, vz, az as uncertain as x, vx, ax, cross terms included (a CA filter's block).
        z_block, x_block = [2, 5, 8], [0, 2, 4]
        rows = np.arange(len(table))[:, None, None]
        cov[rows, np.array(z_block)[:, None], np.array(z_block)] = table.covariance[
            rows, np.array(x_block)[:, None], np.array(x_block)
        ]
        lifted.append(
            pa.TrackTable.from_arrays(
                table.source,
                table.track,
                table.time,
                np.hstack([table.position, pad + 5e3]),
                np.hstack([table.velocity, pad]),
                np.hstack([table.acceleration, pad]),
                cov,
                table.truth,
            )
        )
    correct_3d, _ = score(associator.associate(local=lifted[1], system=lifted[0]), lifted[0], lifted[1], times)
    assert np.nanmean(correct_3d[5:]) > 0.5


def test_radar_against_passive_tracks_of_bearing_fixes() -> None:
    scenario, radar, fixes, passive = demo_tracks(5, PROCESS_NOISE)
    assert fixes.covariance is not None and not np.allclose(fixes.covariance[:, 0, 0], fixes.covariance[:, 1, 1])
    for name, make in METHODS.items():
        correct, _ = score(make().associate(local=passive, system=radar), radar, passive, scenario.scan_times)
        assert np.nanmean(correct[5:]) > 0.5, name


def test_memberships_and_heading_variance() -> None:
    mu = membership(np.array([0.0, 1.0, 1.0, 4.0]), np.array([0.0, 0.0, np.inf, 2.0]), 0.5)
    assert mu.tolist() == [1.0, 0.0, 1.0, pytest.approx(np.exp(-1.0))]
    # 2-D: first-order variance of atan2(vy, vx).
    v = np.array([[[30.0, -40.0]]])
    cov = np.array([[[[4.0, 1.0], [1.0, 9.0]]]])
    _, variance = _heading(v, cov)
    jac = np.array([-v[0, 0, 1], v[0, 0, 0]]) / 50.0**2
    assert variance[0, 0] == pytest.approx(jac @ cov[0, 0] @ jac)
    # At rest there is no heading: infinite variance.
    assert np.isinf(_heading(np.zeros((1, 1, 2)), cov)[1]).all()


def test_empty_sensor_leaves_everything_unpaired() -> None:
    radar, esm, _ = sensor_tracks(6)
    result = pa.WaveletFuzzyAssociator().associate(local=esm.select(np.array([], dtype=np.int64)), system=radar)
    assert len(result.pairs) == 0 and len(result.unpaired_system) == len(radar)


@pytest.mark.parametrize(
    "kwargs,exc,message",
    [
        (dict(window=4), ValueError, "window"),  # sym2 needs 6 scans for one level
        (dict(level=0), ValueError, "level"),
        (dict(wavelet="nope"), ValueError, "wavelet"),
        (dict(wavelet=3), TypeError, "wavelet"),
        (dict(mode="mirror"), ValueError, "mode"),
        (dict(gate_probability=1.0), ValueError, "gate_probability"),
        (dict(weights=(0.5, 0.5, 0.5)), ValueError, "weights"),
        (dict(weights=(0.5, 0.5)), TypeError, "weights"),
        (dict(weights=(1.5, -0.5, 0.0)), ValueError, "weights"),
        (dict(tau=0.0), ValueError, "tau"),
        (dict(epsilon=1.5), ValueError, "epsilon"),
        (dict(whitened=1), TypeError, "whitened"),
        (dict(process_noise=-1.0), ValueError, "process_noise"),
        (dict(process_noise=float("nan")), ValueError, "process_noise"),
        (dict(process_noise=True), TypeError, "process_noise"),
        (dict(process_noise=10.0, whitened=False), ValueError, "process_noise"),
    ],
)
def test_bad_parameters(kwargs: dict[str, object], exc: type[Exception], message: str) -> None:
    with pytest.raises(exc, match=message):
        pa.WaveletFuzzyAssociator(**kwargs)  # type: ignore[arg-type]


def test_bad_tracks() -> None:
    radar, esm, _ = sensor_tracks(7)
    wavelet = pa.WaveletFuzzyAssociator()
    shifted = pa.TrackTable.from_arrays(
        esm.source, esm.track, esm.time + 0.5, esm.position, esm.velocity, esm.acceleration, esm.covariance
    )
    with pytest.raises(ValueError, match=r"local: time 0\.5 s is not a scan time of system"):
        wavelet.associate(local=shifted, system=radar)
    positions_only = pa.TrackTable.from_arrays(radar.source, radar.track, radar.time, radar.position)
    with pytest.raises(ValueError, match=r"system: raw reports \(no velocity column\) need each report's covariance"):
        wavelet.associate(local=esm, system=positions_only)
    no_acceleration = pa.TrackTable.from_arrays(radar.source, radar.track, radar.time, radar.position, radar.velocity)
    with pytest.raises(ValueError, match="system: the method reads the acceleration, covariance"):
        wavelet.associate(local=esm, system=no_acceleration)
    with pytest.raises(ValueError, match="local: the method reads the covariance"):
        pa.Chi2TrackAssociator().associate(
            local=pa.TrackTable.from_arrays(esm.source, esm.track, esm.time, esm.position), system=radar
        )
    both = pa.TrackTable.from_arrays(
        np.concatenate([radar.source, esm.source]),
        np.concatenate([radar.track, esm.track]),
        np.concatenate([radar.time, esm.time]),
        np.concatenate([radar.position, esm.position]),
    )
    with pytest.raises(ValueError, match=r"system: one sensor's tracks expected, got sources \[0, 1\]"):
        pa.NearestNeighbourAssociator().associate(local=esm, system=both)
    with pytest.raises(TypeError, match="local: expected a TrackTable"):
        wavelet.associate(local=esm.position, system=radar)  # type: ignore[arg-type]
    # NaN states never reach an associator: the track table refuses them, naming the column.
    velocity = np.array(esm.velocity)
    velocity[3, 0] = np.nan
    with pytest.raises(ValueError, match="velocity"):
        pa.TrackTable.from_arrays(esm.source, esm.track, esm.time, esm.position, velocity)


@pytest.mark.parametrize("method", METHODS)
def test_a_table_that_is_not_a_track_table_is_a_type_error(method: str) -> None:
    """Chi2TrackAssociator read the tables' blocks before checking them (AttributeError)."""
    radar, esm, _ = sensor_tracks(7)
    with pytest.raises(TypeError, match="system: expected a TrackTable"):
        METHODS[method]().associate(local=esm, system=radar.to_arrays())  # type: ignore[arg-type]
    with pytest.raises(TypeError, match="local: expected a TrackTable"):
        METHODS[method]().associate(local=esm.position, system=radar)  # type: ignore[arg-type]


@pytest.mark.parametrize("whitened", [True, False])
def test_the_associators_gate_is_coarse_gate(whitened: bool) -> None:
    """The associator calls the core with cached operators and thresholds; same answer as the
    public, fully checked coarse_gate."""
    rng = np.random.default_rng(8)
    radar_x = rng.normal(0.0, 1e3, (7, 2, 20))
    esm_x = np.ascontiguousarray(radar_x[rng.permutation(7)] + rng.normal(0.0, 200.0, (7, 2, 20)))
    var_r, var_e = rng.uniform(1e4, 1e5, (2, 7, 2, 20))
    associator = pa.WaveletFuzzyAssociator(whitened=whitened, mode="periodization")
    expected = coarse_gate(radar_x, var_r, esm_x, var_e, whitened=whitened, mode="periodization").passed
    assert expected.any() and not expected.all()
    assert np.array_equal(gate_diagonal(associator, radar_x, var_r, esm_x, var_e), expected)


def test_sensors_of_different_dimension_are_refused() -> None:
    radar, _, _ = sensor_tracks(9)
    _, esm_2d, _ = sensor_tracks(9, ndim=2)
    with pytest.raises(ValueError, match="local: has 2-D positions, system has 1-D"):
        pa.WaveletFuzzyAssociator().associate(local=esm_2d, system=radar)
