"""Regenerates the example files the README's "your own data" commands read (fixed seeds):

* ``initiate_sensors.csv`` / ``initiate_measurements.csv`` — the fuzzy-track-initiation paper's
  scene (2 sensors, 3-D, 4 targets, 8 scans, clutter), seed 1;
* ``associate_sensors.csv`` / ``associate_measurements.csv`` — three scans of the static
  association paper's scene (3 sensors, 2-D, 5 targets, misses and false alarms), seeds 1–3,
  one scan per time (0, 10, 20 s);
* ``locate_sensors.csv`` / ``locate_measurements.csv`` — one snapshot of the formation paper's
  scene (3 sensors, 2-D, 6 emitters, 1° bearing noise), seed 1, with the emitter attributes
  ``rf``, ``prf``, ``pw``, ``asp`` and their per-report stds (``<name>_std``).

    python3 examples/make_examples.py
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import passive_assoc as pa
from passive_assoc.simulation import paper_fti_scenario, static_scan
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


if __name__ == "__main__":
    main()
