"""The one nearest-neighbour track associator: distances in the tables' own dimension, the
position χ² gate from the tracks' covariances, the gate in metres, and every track in one
pair or unpaired."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.radar_esm import position_gate_pairs


def picture(source: int, positions: np.ndarray, variance: float | None = None) -> pa.TrackTable:
    n, d = positions.shape
    covariance = None if variance is None else np.tile(np.eye(d) * variance, (n, 1, 1))
    return pa.TrackTable.from_arrays(np.full(n, source), np.arange(n), np.zeros(n), positions, covariance=covariance)


def pairs_of(result: pa.TrackAssociation) -> set[tuple[int, int]]:
    return set(zip(result.pairs.local_track.tolist(), result.pairs.system_track.tolist(), strict=True))


def check_partition(result: pa.TrackAssociation, local: pa.TrackTable, system: pa.TrackTable) -> None:
    assert len(result.pairs) + len(result.unpaired_local) == len(local)
    assert len(result.pairs) + len(result.unpaired_system) == len(system)
    assert len(set(result.pairs.local_track.tolist())) == len(result.pairs)


def test_distances_are_three_dimensional() -> None:
    """Two system tracks at the same (x, y), one 5 km higher: the local track at the higher
    one's height pairs with it (a planar distance would tie)."""
    system = picture(0, np.array([[0.0, 0.0, 1e3], [0.0, 0.0, 6e3], [50e3, 0.0, 1e3]]))
    local = picture(1, np.array([[10.0, 0.0, 6e3], [50e3, 10.0, 1e3]]))
    result = pa.NearestNeighbourAssociator().associate(local=local, system=system)
    assert pairs_of(result) == {(0, 1), (1, 2)}
    check_partition(result, local, system)


def test_chi2_gate_leaves_a_track_without_partner_unpaired() -> None:
    """Tracks with 100 m standard deviations: a local track 5 km from every system track is
    outside the 99 % gate and stays unpaired; without the gate it would be paired."""
    system = picture(0, np.array([[0.0, 0.0], [20e3, 0.0]]), variance=100.0**2)
    local = picture(1, np.array([[30.0, -20.0], [10e3, 0.0]]), variance=100.0**2)
    gated = pa.NearestNeighbourAssociator().associate(local=local, system=system)
    assert pairs_of(gated) == {(0, 0)}
    assert gated.unpaired_local.track.tolist() == [1]
    check_partition(gated, local, system)
    ungated = pa.NearestNeighbourAssociator(gate_probability=None).associate(local=local, system=system)
    assert pairs_of(ungated) == {(0, 0), (1, 1)}  # the most pairs, then the least distance
    gate_pairs = position_gate_pairs(local=local, system=system, gate_probability=0.99)
    assert set(zip(gate_pairs.local_track.tolist(), gate_pairs.system_track.tolist(), strict=True)) == {(0, 0)}


def test_gate_in_metres() -> None:
    system = picture(0, np.array([[0.0, 0.0], [20e3, 0.0]]))
    local = picture(1, np.array([[100.0, 0.0], [27e3, 0.0]]))
    result = pa.NearestNeighbourAssociator(gate=5e3).associate(local=local, system=system)
    assert pairs_of(result) == {(0, 0)}
    check_partition(result, local, system)


def test_one_dimensional_tracks() -> None:
    """Positions on one axis (the radar/ESM paper's scenario): gated by the 1-D χ² test."""
    system = picture(0, np.array([[0.0], [1e3], [5e3]]), variance=50.0**2)
    local = picture(1, np.array([[990.0], [20.0], [9e3]]), variance=50.0**2)
    result = pa.NearestNeighbourAssociator().associate(local=local, system=system)
    assert pairs_of(result) == {(0, 1), (1, 0)}
    assert result.unpaired_local.track.tolist() == [2]
    check_partition(result, local, system)


def test_mismatched_dimensions_are_refused() -> None:
    system = picture(0, np.array([[0.0, 0.0], [1.0, 0.0]]))
    local = picture(1, np.array([[0.0, 0.0, 0.0]]))
    with pytest.raises(ValueError, match="system: has 2-D positions, local has 3-D"):
        pa.NearestNeighbourAssociator().associate(local=local, system=system)


_PAIR_CAP_SCRIPT = """
import resource
import subprocess
import sys

import numpy as np
import passive_assoc as pa

resource.setrlimit(resource.RLIMIT_AS, (1 << 30, 1 << 30))  # 1 GB of address space
rng = np.random.default_rng(0)

def pictures(n, covariance=False):
    p = rng.uniform(0, 1e6, (n, 2))
    cov = np.tile(np.eye(4) * 100.0, (n, 1, 1)) if covariance else None
    def table(source, position):
        return pa.TrackTable.from_arrays(
            np.full(n, source), np.arange(n), np.zeros(n), position, velocity=np.zeros((n, 2)), covariance=cov
        )
    return table(1, p + rng.normal(0, 10, (n, 2))), table(0, p)

cases = [
    ("ungated", pictures(4_001), {}),
    ("chi2", pictures(4_001, covariance=True), {}),
    ("wide gate", pictures(5_000), {"gate": 1e9}),
    ("wide gate and chi2", pictures(5_000, covariance=True), {"gate": 1e9}),
]
for name, (local, system), settings in cases:
    for associator in (pa.NearestNeighbourAssociator(**settings), pa.TopologyAssociator(gate=settings.get("gate"))):
        try:
            out = associator.associate(local=local, system=system, progress=False)
            print(name, "associated", len(out.pairs))
        except ValueError as err:
            print(name, str(err).split(";")[0])
"""


@pytest.mark.skipif(sys.platform != "linux", reason="RLIMIT_AS is how the test bounds memory")
def test_the_pair_cap_binds_with_and_without_gates_in_bounded_memory() -> None:
    """One 20 000 × 20 000 scan aborted the nearest-neighbour associator (an allocation of
    268 MB failed) and 10 000 × 10 000 peaked at 1.48 GB; a position gate wider than the
    picture listed every pair (5 000 × 5 000: 1.8 GB), and the χ² gate was applied only
    after listing them. Under a 1 GB address-space limit each is refused, naming the cap, or
    (the χ² gate tested as pairs are listed) associated."""
    done = subprocess.run([sys.executable, "-c", _PAIR_CAP_SCRIPT], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    cap = "track pairs in one scan: {} exceeds the cap of {}"
    assert done.stdout.splitlines() == [
        "ungated " + cap.format(16008001, 16000000),
        "ungated " + cap.format(16008001, 4000000),  # the topology default window of 6
        "chi2 " + cap.format(16008001, 16000000),  # the χ² gate alone tests every pair
        "chi2 " + cap.format(16008001, 4000000),
        "wide gate " + cap.format(16000001, 16000000),
        "wide gate " + cap.format(4000001, 4000000),
        "wide gate and chi2 associated 5000",
        "wide gate and chi2 " + cap.format(4000001, 4000000),  # topology has no χ² gate
    ], done.stdout
