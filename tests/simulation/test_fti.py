"""The fuzzy-track-initiation paper's scenario against its specification (METHODS §1)."""

from __future__ import annotations

import math

import numpy as np
from passive_assoc.simulation import PAPER_FTI_TARGETS, paper_fti_scenario


def test_paper_scenario_matches_spec() -> None:
    scen = paper_fti_scenario(seed=1)
    assert PAPER_FTI_TARGETS.shape == (4, 6)
    assert PAPER_FTI_TARGETS[0].tolist() == [1340, 15000, 1000, 173.2, -100, 0]
    assert scen.sensors.positions.tolist() == [[0, 0, 0], [20000, 0, 0]]
    assert np.all(scen.sensors.sigma_azimuth == 5e-3)
    assert np.all(scen.sensors.sigma_elevation == 5e-3)
    assert scen.scan_times[0].tolist() == [15.0 * k for k in range(8)]
    assert scen.scan_times[1].tolist() == [5.0 + 15.0 * k for k in range(8)]
    assert scen.t0 == 0.0 and np.array_equal(scen.true_states, PAPER_FTI_TARGETS)
    m = scen.measurements
    assert len(m) == 2 * 8 * (4 + 8) and m.ndim == 3
    for j in range(2):
        for t in scen.scan_times[j]:
            scan = (m.sensor == j) & (m.time == t)
            assert np.sum(m.truth[scan] == -1) == 8  # clutter = 2 x 4 targets, exactly
            assert sorted(m.truth[scan][m.truth[scan] >= 0]) == [0, 1, 2, 3]
    clutter = m.truth == -1
    assert np.all((m.azimuth[clutter] >= 0) & (m.azimuth[clutter] <= math.pi))
    assert np.all((m.elevation[clutter] >= 0) & (m.elevation[clutter] <= math.pi / 2))
    m.validate_against(scen.sensors)
    groups = scen.true_groups()
    assert [g.size for g in groups] == [16] * 4 and np.all(m.truth[groups[2]] == 2)
