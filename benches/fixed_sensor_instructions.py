"""Fixed-sensor workloads for instruction counts, which the machine's load does not move: run
each under callgrind for two builds (their packages on ``PYTHONPATH``) and subtract the
``none`` run (imports and simulation only) of the same build.

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=<package dir> valgrind --tool=callgrind \\
        --callgrind-out-file=/dev/null python3 benches/fixed_sensor_instructions.py static

Workloads: ``none``; ``static`` and ``intensity`` (`associate_static` on three 20-target scans
of the static-association paper's scene, one thread); ``initiate`` (`FuzzyTrackInitiator` on
three paper runs); ``fit`` (`fit_ml` of the paper's targets from their true rows, 60 calls).
OpenBLAS's own threads spin and move the counts by up to 13 %: keep them at one.
"""

from __future__ import annotations

import argparse
import warnings

import passive_assoc as pa
from passive_assoc.estimation import fit_ml
from passive_assoc.simulation import static_scan


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("workload", choices=("none", "static", "intensity", "initiate", "fit"))
    what = parser.parse_args().workload
    warnings.simplefilter("ignore")
    scans = [static_scan(s, n_targets=20) for s in range(3)]
    paper = [pa.paper_fti_scenario(s) for s in range(3)]
    if what in ("static", "intensity"):
        for scan in scans:
            if what == "static":
                pa.associate_static(scan.measurements, scan.sensors, "lagrangian", n_threads=1)
            else:
                pa.associate_static(scan.measurements, scan.sensors, "intensity", n_threads=1)
    elif what == "initiate":
        for sc in paper:
            pa.FuzzyTrackInitiator(n_threads=1).initiate(sc.measurements, sc.sensors, t0=sc.t0, progress=False)
    elif what == "fit":
        for sc in paper:
            for _ in range(20):
                fit_ml(sc.measurements, sc.sensors, sc.true_groups(), t0=sc.t0, n_threads=1)


if __name__ == "__main__":
    main()
