"""The CRLB is returned symmetric even where the Fisher information is ill-conditioned."""

from __future__ import annotations

import numpy as np
import passive_assoc as pa


def test_crlb_is_symmetric_for_a_very_fast_target() -> None:
    scenario = pa.paper_fti_scenario(1)
    table, sensors = scenario.measurements, scenario.sensors
    rows = scenario.true_groups()[0]
    state = np.array(scenario.true_states[0], dtype=float)
    state[3:] *= 1e6  # ~1e8 m/s: here a Cholesky inverse is asymmetric by 4e7
    bound = pa.crlb(table.sensor[rows], table.time[rows], sensors, state)
    assert np.array_equal(bound, bound.T)
    assert np.isfinite(bound).all()
