"""The topology experiments' local tracks: each radar's tracks of a
:class:`~passive_assoc.simulation.topology.RadarScenario`, filtered from its own biased
reports, and how far off a bias estimate may be before it counts as a gross failure. Shared by
the paper's scene (:mod:`.topology`) and the ring scene (:mod:`.topology_ring`)."""

from __future__ import annotations

import numpy as np

from ..data import TrackTable
from ..estimation.kalman import KalmanFilter
from ..simulation.topology import RadarScenario

#: White-acceleration spectral density of the local trackers (m²/s³). The targets fly
#: straight at constant speed (the truth's q is 0); 0.1 lets the velocity wander ~0.3 m/s per
#: 10 s scan. docs/experiments.md shows the result barely depends on it (0.01 to 1).
PROCESS_NOISE = 0.1
#: A bias estimate further than this from the truth (degrees) is counted as a gross failure.
GROSS_BIAS_DEG = 1.0


def local_tracks(scenario: RadarScenario, rng: np.random.Generator, process_noise: float = PROCESS_NOISE) -> TrackTable:
    """Every radar's tracks: a CV EKF per (radar, target) on its own range/azimuth reports,
    positions in the radar's own biased frame (with the filter's covariance), ids shuffled per
    radar. (The radar's own
    report-to-track assignment is taken as given: it is not the method under test.)"""
    m = scenario.measurements
    groups, track_ids = [], []
    for radar in range(len(scenario.radars)):
        rows_of_radar = np.flatnonzero(m.radar == radar)
        targets = np.unique(m.truth[rows_of_radar])
        shuffled = rng.permutation(len(targets))
        for k, target in enumerate(targets):
            rows = rows_of_radar[m.truth[rows_of_radar] == target]
            groups.append(rows[np.argsort(m.time[rows], kind="stable")])
            track_ids.append(int(shuffled[k]))
    radar_at = np.array([r.position for r in scenario.radars])[m.radar]
    noise = np.array([[r.sigma_range, r.sigma_azimuth] for r in scenario.radars])[m.radar]
    kf = KalmanFilter(motion="cv", measurement="polar", process_noise=process_noise, n_threads=1)
    out = kf.filter(m.time, np.column_stack([m.range, m.azimuth]), groups, noise=noise, sensor_positions=radar_at)
    rows = np.concatenate(groups)
    track = np.concatenate([np.full(len(g), tid) for g, tid in zip(groups, track_ids, strict=True)])
    keep = out.has_state[rows]
    rows, track = rows[keep], track[keep]
    return TrackTable.from_arrays(
        m.radar[rows],
        track,
        m.time[rows],
        out.states[rows, :2],
        velocity=out.states[rows, 2:4],
        covariance=out.covariances[rows],
        truth=m.truth[rows],
        sort=True,
    )
