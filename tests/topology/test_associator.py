"""Track-to-track association by reference topology (METHODS §4) through the public API:
nothing lost, ids do not matter, bias is recovered, bad input is refused."""

from __future__ import annotations

import numpy as np
import passive_assoc as pa
import pytest
from passive_assoc.evaluation import track_association_scores
from passive_assoc.simulation.topology import paper_topology_scenario
from passive_assoc.topology import topology_vectors

#: The nearest-neighbour baseline as the topology experiment runs it.
NEAREST = {"gate": 60e3, "window": 6, "gate_probability": None}


def measured_tracks(seed: int, bias_deg: float) -> tuple[pa.TrackTable, pa.TrackTable, object]:
    """Each radar's reports as one-scan tracks (no filter), ids shuffled per radar: the local
    pictures (radars 1..7) and the system picture (radar 0)."""
    rng = np.random.default_rng(seed)
    scenario = paper_topology_scenario(rng, bias_deg=bias_deg, n_scans=12)
    m = scenario.measurements
    ids = np.empty(len(m), np.int64)
    for radar in range(len(scenario.radars)):
        rows = m.radar == radar
        ids[rows] = rng.permutation(len(scenario.targets))[m.truth[rows]]
    tracks = pa.TrackTable.from_arrays(m.radar, ids, m.time, m.to_cartesian(), truth=m.truth, sort=True)
    return tracks.select(np.flatnonzero(tracks.source != 0)), tracks.of(0), scenario


def test_every_track_of_every_scan_is_paired_or_unpaired() -> None:
    local, system, _ = measured_tracks(1, 5.0)
    result = pa.TopologyAssociator().associate(local=local, system=system)
    assert len(result.pairs) > 0.9 * len(local), "most tracks are paired: the check is not vacuous"
    seen = [(t, s, k) for t, s, k in zip(result.pairs.time, result.pairs.source, result.pairs.local_track, strict=True)]
    u = result.unpaired_local
    seen += list(zip(u.time, u.source, u.track, strict=True))
    expected = list(zip(local.time, local.source, local.track, strict=True))
    assert sorted(seen) == sorted(expected) and len(set(seen)) == len(seen)
    # System tracks, per source and scan: paired once or unpaired once.
    sys_seen = list(zip(result.pairs.time, result.pairs.source, result.pairs.system_track, strict=True))
    v = result.unpaired_system
    sys_seen += list(zip(v.time, v.source, v.track, strict=True))
    expected_sys = [(t, s, k) for s in local.sources for t, k in zip(system.time, system.track, strict=True)]
    assert sorted(sys_seen) == sorted(expected_sys)


@pytest.mark.parametrize("method", [pa.TopologyAssociator, pa.NearestNeighbourAssociator])
def test_system_tracks_are_kept_where_a_source_has_no_track(
    method: type[pa.TopologyAssociator] | type[pa.NearestNeighbourAssociator],
) -> None:
    """A source with no track at one scan, and a scan only the system table has: every system
    track there is unpaired for each source, none left out of the result."""
    local, system, _ = measured_tracks(7, 1.0)
    times = system.scan_times()
    sources = local.sources
    local = local.select(~((local.source == sources[0]) & (local.time == times[3])) & (local.time != times[-1]))
    result = method().associate(local=local, system=system)
    sys_seen = list(zip(result.pairs.time, result.pairs.source, result.pairs.system_track, strict=True))
    v = result.unpaired_system
    sys_seen += list(zip(v.time, v.source, v.track, strict=True))
    expected_sys = [(t, s, k) for s in sources for t, k in zip(system.time, system.track, strict=True)]
    assert sorted(sys_seen) == sorted(expected_sys)
    at_gap = (v.time == times[3]) & (v.source == sources[0])
    assert sorted(v.track[at_gap].tolist()) == sorted(system.at(float(times[3])).track.tolist())
    # Streaming: a source seen before and silent now leaves the system tracks unpaired too.
    live = method()
    live.update(local=local.at(float(times[0])), system=system.at(float(times[0])))
    out = live.update(
        local=local.select(local.source != sources[0]).at(float(times[1])), system=system.at(float(times[1]))
    )
    assert sorted(out.unpaired_system.track[out.unpaired_system.source == sources[0]].tolist()) == sorted(
        system.at(float(times[1])).track.tolist()
    )


def test_topology_survives_bias_where_nearest_neighbour_does_not() -> None:
    """On the radar whose bias differs most from the system radar's (5.1° here), nearest
    neighbour pairs targets 20-30 km apart wrongly; topology does not (measured at this seed:
    F1 0.96 against 0.56)."""
    local, system, scenario = measured_tracks(2, 5.0)
    relative = np.degrees(scenario.true_biases - scenario.true_biases[0])  # type: ignore[attr-defined]
    worst = int(np.argmax(np.abs(relative[1:]))) + 1
    assert abs(relative[worst]) > 4.0
    one = local.of(worst)
    since = float(scenario.scan_times[5])  # type: ignore[attr-defined]
    topo = track_association_scores(
        pa.TopologyAssociator().associate(local=one, system=system), one, system, since=since
    )
    near = track_association_scores(
        pa.NearestNeighbourAssociator(**NEAREST).associate(local=one, system=system), one, system, since=since
    )
    assert topo.f1 > 0.9
    assert near.f1 < 0.8


def test_bias_is_estimated() -> None:
    local, system, scenario = measured_tracks(3, 5.0)
    result = pa.TopologyAssociator().associate(local=local, system=system)
    truth = scenario.true_biases - scenario.true_biases[0]  # type: ignore[attr-defined]
    for radar, estimate in result.bias.items():
        assert abs(estimate.rotation - truth[radar]) < max(5 * estimate.rotation_std, np.radians(0.3)), radar
        assert estimate.pairs > 0


def test_track_ids_do_not_matter() -> None:
    local, system, _ = measured_tracks(4, 3.0)
    relabel = 1000 + np.random.default_rng(0).permutation(int(local.track.max()) + 1)
    renamed = pa.TrackTable.from_arrays(
        local.source, relabel[local.track], local.time, local.position, truth=local.truth, sort=True
    )
    a = pa.TopologyAssociator().associate(local=local, system=system)
    b = pa.TopologyAssociator().associate(local=renamed, system=system)
    key_a = sorted(zip(a.pairs.time, a.pairs.source, relabel[a.pairs.local_track], a.pairs.system_track, strict=True))
    key_b = sorted(zip(b.pairs.time, b.pairs.source, b.pairs.local_track, b.pairs.system_track, strict=True))
    assert key_a == key_b


def test_streaming_update_equals_associate() -> None:
    local, system, _ = measured_tracks(5, 1.0)
    batch = pa.TopologyAssociator().associate(local=local, system=system)
    live = pa.TopologyAssociator()
    parts = [live.update(local=local.at(t), system=system.at(t)) for t in local.scan_times()]
    assert np.array_equal(np.concatenate([p.pairs.local_track for p in parts]), batch.pairs.local_track)
    assert np.array_equal(np.concatenate([p.pairs.system_track for p in parts]), batch.pairs.system_track)


def test_an_empty_system_picture_leaves_everything_unpaired() -> None:
    local, system, _ = measured_tracks(6, 0.0)
    empty = system.select(np.array([], dtype=np.int64))
    result = pa.TopologyAssociator().associate(local=local, system=empty)
    assert len(result.pairs) == 0 and len(result.unpaired_local) == len(local)


@pytest.mark.parametrize(
    "kwargs,exc,message",
    [
        (dict(rings=0), ValueError, "rings"),
        (dict(sectors=2.5), TypeError, "sectors"),
        (dict(delta=1.5), ValueError, "delta"),
        (dict(delta_prime=-0.1), ValueError, "delta_prime"),
        (dict(threshold=2.0), ValueError, "threshold"),
        (dict(window=0), ValueError, "window"),
        (dict(gate=-1.0), ValueError, "gate"),
        (dict(diffusion="sum"), ValueError, "diffusion"),
        (dict(heading_reference=1), TypeError, "heading_reference"),
    ],
)
def test_bad_parameters(kwargs: dict[str, object], exc: type[Exception], message: str) -> None:
    with pytest.raises(exc, match=message):
        pa.TopologyAssociator(**kwargs)  # type: ignore[arg-type]


def test_bad_tracks() -> None:
    local, system, _ = measured_tracks(7, 0.0)
    one_d = pa.TrackTable.from_arrays(local.source, local.track, local.time, local.position[:, 0], sort=True)
    with pytest.raises(ValueError, match="2-D or 3-D"):
        pa.TopologyAssociator().associate(local=one_d, system=system)
    with pytest.raises(ValueError, match="velocities"):
        pa.TopologyAssociator(heading_reference=True).associate(local=local, system=system)
    with pytest.raises(ValueError, match="one scan"):
        pa.TopologyAssociator().update(local=local, system=system)


@pytest.mark.parametrize("associator", [pa.TopologyAssociator(), pa.NearestNeighbourAssociator()])
def test_local_tracks_of_another_dimension_than_the_system_picture_are_refused(
    associator: pa.TopologyAssociator | pa.NearestNeighbourAssociator,
) -> None:
    """3-D local tracks against a 2-D system picture (or the reverse), in one call or a scan
    at a time: refused before any pairing, naming both dimensions."""
    local, system, _ = measured_tracks(7, 0.0)
    at = system.time[0]
    flat, scan = system.at(at), local.at(at)
    raised = pa.TrackTable.from_arrays(
        scan.source, scan.track, scan.time, np.column_stack([scan.position, np.full(len(scan), 3e3)])
    )
    for call in (associator.associate, associator.update):
        with pytest.raises(ValueError, match="system: has 2-D positions, local has 3-D"):
            call(local=raised, system=flat)
    lifted = pa.TrackTable.from_arrays(
        flat.source, flat.track, flat.time, np.column_stack([flat.position, np.zeros(len(flat))])
    )
    with pytest.raises(ValueError, match="system: has 3-D positions, local has 2-D"):
        associator.update(local=scan, system=lifted)


def test_correcting_the_estimated_bias_rescues_nearest_neighbour() -> None:
    """The topology pass estimates each radar's bias; turning the local pictures back by it
    makes plain distance association work again (and correct_bias runs that second pass)."""
    from passive_assoc.topology import unbias

    local, system, scenario = measured_tracks(2, 5.0)
    since = float(scenario.scan_times[5])  # type: ignore[attr-defined]
    first = pa.TopologyAssociator().associate(local=local, system=system)
    corrected = unbias(local, first.bias)
    near_before = track_association_scores(
        pa.NearestNeighbourAssociator(**NEAREST).associate(local=local, system=system), local, system, since=since
    )
    near_after = track_association_scores(
        pa.NearestNeighbourAssociator(**NEAREST).associate(local=corrected, system=system),
        corrected,
        system,
        since=since,
    )
    # Measured at this seed: 0.938 before, over 0.99 after.
    assert near_before.f1 < 0.95 < 0.99 < near_after.f1
    twice = pa.TopologyAssociator(correct_bias=True).associate(local=local, system=system)
    assert len(twice.pairs) > 0.9 * len(local)
    # The bias reported is the final pass's: the first pass's turn composed with what the
    # second found left; it agrees with the first pass's within their spreads.
    truth = scenario.true_biases - scenario.true_biases[0]  # type: ignore[attr-defined]
    for radar, b in twice.bias.items():
        assert b != first.bias[radar]
        assert abs(b.rotation - first.bias[radar].rotation) <= 3 * max(b.rotation_std, first.bias[radar].rotation_std)
        assert abs(b.rotation - truth[radar]) <= 3 * b.rotation_std, radar


def test_topology_vectors_refuse_what_they_cannot_use() -> None:
    """A heading-referenced grid without velocities silently fell back to north; a non-table
    raised AttributeError."""
    tracks = pa.TrackTable.from_arrays([0, 0], [0, 1], [0.0, 0.0], [[0.0, 0.0], [1e3, 1e3]])
    with pytest.raises(ValueError, match="tracks: the heading-referenced grid needs velocities"):
        topology_vectors(tracks, pa.TopologyAssociator(heading_reference=True))
    with pytest.raises(TypeError, match="tracks: expected a TrackTable"):
        topology_vectors(tracks.position)  # type: ignore[arg-type]
    assert topology_vectors(tracks).shape == (2, 48)
