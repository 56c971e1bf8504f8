"""Regenerates the example files the README's "your own data" commands read (fixed seeds):

* ``initiate_sensors.csv`` / ``initiate_measurements.csv`` — the fuzzy-track-initiation paper's
  scene (2 sensors, 3-D, 4 targets, 8 scans, clutter), seed 1;
* ``associate_sensors.csv`` / ``associate_measurements.csv`` — three scans of the static
  association paper's scene (3 sensors, 2-D, 5 targets, misses and false alarms), seeds 1–3,
  one scan per time (0, 10, 20 s);
* ``locate_sensors.csv`` / ``locate_measurements.csv`` — one snapshot of the formation paper's
  scene (3 sensors, 2-D, 6 emitters, 1° bearing noise), seed 1, with the emitter attributes
  ``rf``, ``prf``, ``pw``, ``asp`` and their per-report stds (``<name>_std``);
* ``topology_local.csv`` / ``topology_system.csv`` — the topology paper's radars (seed 1,
  relative azimuth biases up to 3°), tracks filtered from their reports over the first 12
  scans: the system radar's and the others' (positions and velocities, without the filter's
  covariances, to keep the files small: the topology associator then weighs distances by the
  scatter of its own bias fit);
* ``wavelet_radar.csv`` / ``wavelet_esm.csv`` — the wavelet paper's radar and ESM tracks
  (seed 1, one false track each), constant-acceleration filtered from a prior at the first
  report.

    python3 examples/make_examples.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import passive_assoc as pa
from passive_assoc.experiments.topology import SYSTEM_RADAR, local_tracks
from passive_assoc.experiments.wavelet import PROCESS_NOISE
from passive_assoc.radar_esm import filter_reports
from passive_assoc.simulation import paper_fti_scenario, paper_topology_scenario, paper_wavelet_scenario, static_scan
from passive_assoc.simulation.formation import paper_formation_scene

HERE = Path(__file__).resolve().parent


def main() -> None:
    fti = paper_fti_scenario(seed=1)
    fti.sensors.to_csv(HERE / "initiate_sensors.csv")
    fti.measurements.to_csv(HERE / "initiate_measurements.csv")
    scans = [static_scan(seed, n_targets=5) for seed in (1, 2, 3)]
    scans[0].sensors.to_csv(HERE / "associate_sensors.csv")
    parts = [s.measurements.to_arrays() for s in scans]
    columns = {name: np.concatenate([p[name] for p in parts]) for name in parts[0]}
    columns["time"] = np.concatenate([np.full(len(p["time"]), 10.0 * k) for k, p in enumerate(parts)])
    pa.MeasurementTable.from_columns(columns).to_csv(HERE / "associate_measurements.csv")
    scene = paper_formation_scene(1, 1.0, "realistic")
    scene.sensors.to_csv(HERE / "locate_sensors.csv")
    columns = scene.measurements.to_arrays()
    n = len(columns["time"])
    for name, std in scene.attribute_std.items():
        columns[f"attr_{name}_std"] = np.full(n, float(std))
    pa.MeasurementTable.from_columns(columns).to_csv(HERE / "locate_measurements.csv")
    rng = np.random.default_rng(1)
    scenario = paper_topology_scenario(rng, bias_deg=3.0)
    tracks = local_tracks(scenario, rng)
    tracks = tracks.select(np.flatnonzero(tracks.time <= scenario.scan_times[11]))  # 12 scans: a small file
    tracks = pa.TrackTable.from_arrays(
        tracks.source, tracks.track, tracks.time, tracks.position, velocity=tracks.velocity, truth=tracks.truth
    )
    tracks.of(SYSTEM_RADAR).to_csv(HERE / "topology_system.csv")
    tracks.select(np.flatnonzero(tracks.source != SYSTEM_RADAR)).to_csv(HERE / "topology_local.csv")
    filtered = filter_reports(paper_wavelet_scenario(1, n_clutter=1).measurements, PROCESS_NOISE)
    filtered.of(0).to_csv(HERE / "wavelet_radar.csv")
    filtered.of(1).to_csv(HERE / "wavelet_esm.csv")


if __name__ == "__main__":
    main()
