"""``passive-assoc associate MEAS --sensors SENS``: static association (METHODS §2) of every
scan of the user's measurement file.

Rows are grouped into scans by ``--scan-column`` (default ``time``: rows with the same time
form a scan; or any attribute column of the file, e.g. a scan number). With
``--scan-window SECONDS`` reports within that window form a scan
(:func:`passive_assoc.static_los.window_scans`' rule): the clocks of real sensors jitter. A
time column that gives no scan with two sensors is refused with that advice. Each scan is
associated on its own. Writes, in ``--out`` (``<prefix>``: MEAS's file name without its
extension, or ``--prefix``):

* ``<prefix>.associate.csv`` — every input row once: row, sensor, time, angles, ``scan``
  (its index) and ``target`` (the located target's index over the whole file, or −1 for a
  false alarm);
* ``<prefix>.associate.json`` — per target: its scan, position, covariance, cost and rows.
"""

from __future__ import annotations

import argparse
import sys
import warnings
from typing import Any

import numpy as np
from tqdm import tqdm

from .._params import field_defaults
from ..assignment import assign_sd
from ..formation import FormationLocator
from ..static_los import StaticAssociator
from ..static_los.batch import scan_keys, scan_rows
from .common import (
    EXAMPLE_FORMATS,
    add_file_arguments,
    add_parameter_options,
    given_parameters,
    output_path,
    outputs_epilog,
    parameter_docs,
    plan_outputs,
    read_inputs,
    row_columns,
    with_geodetic,
    write_atomically,
    write_outputs,
)

__all__ = ["add_arguments", "column_name", "main"]

DESCRIPTION = (
    "Associate the bearings (and elevations) of several passive sensors scan by scan: which "
    "reports are the same target, where it is, and which are false alarms (METHODS §2: the "
    "intensity search, or S-D assignment by Lagrangian relaxation or exactly)."
)

#: When to choose each --method, with the reason measured by benches/static_method_choice.py
#: (the shipped example's 3 scans, and 120 simulated scans of 5-20 targets, 3-5 sensors,
#: Pd 0.8-0.95: 1277 targets seen by two sensors or more).
METHODS_HELP = """methods (--method), measured by benches/static_method_choice.py (targets found exactly):
  lagrangian  default, right most often for its time: 27 % of targets, 11 of the example's 15; 1-6 ms/scan
  exact       the proven optimum, for small scans: 28 % of targets, but 0.1-2.3 s/scan at 10-20 targets
  intensity   the paper's search, to reproduce paper 001: as fast, but 13.5 % of targets, 4 of 15
"""


def add_arguments(parser: argparse.ArgumentParser) -> None:
    parser.description = DESCRIPTION
    parser.epilog = (
        EXAMPLE_FORMATS
        + "\n"
        + METHODS_HELP
        + "\n"
        + outputs_epilog(
            "associate",
            "MEAS",
            "every input row once, with its scan and target (-1: false alarm)",
            "per target: scan, position, covariance, cost, rows",
        )
        + "\nexamples:\n  passive-assoc associate examples/associate_measurements.csv "
        + "--sensors examples/associate_sensors.csv --out out/\n"
        + "  passive-assoc associate examples/associate_measurements.csv "
        + "--sensors examples/associate_sensors.csv --method exact --prefix exact --out out/"
    )
    parser.formatter_class = argparse.RawDescriptionHelpFormatter
    add_file_arguments(parser, "associate")
    parser.add_argument(
        "--scan-column",
        metavar="NAME",
        type=column_name,
        default="time",
        help="rows with equal values in this column form one scan: 'time' (default) or an attribute column; "
        "with --scan-window, reports within that many seconds form a scan",
    )
    parser.add_argument(
        "--plot", metavar="FILE", type=output_path, help="save a figure of the sensors, lines of sight and targets"
    )
    defaults = field_defaults(StaticAssociator)
    # "method" is a parameter of the associator like any other: --method.
    docs = parameter_docs(StaticAssociator)
    # Its entries that point elsewhere ("Solver settings, as in assign_sd"): the sentence there.
    docs.update({k: v for k, v in parameter_docs(assign_sd).items() if " as in " in docs.get(k, "")})
    docs.update({k: v for k, v in parameter_docs(FormationLocator).items() if " as in " in docs.get(k, "")})
    names = add_parameter_options(parser, StaticAssociator._constraints, defaults, docs=docs)
    parser.set_defaults(parameter_names=names)


def column_name(text: str) -> str:
    """argparse type: a column name (checked against the file once it is read)."""
    if not text.strip():
        raise argparse.ArgumentTypeError("expected a column name, got an empty string")
    return text.strip()


column_name.bad_values = ["", "  "]  # type: ignore[attr-defined]


def check_scans_have_two_sensors(table: Any, scan: Any, n_scans: int) -> None:
    """A ValueError when exact times give no scan with two sensors (jittered clocks: nothing
    could be associated), naming the option that groups them."""
    sensors_per_scan = np.zeros(n_scans, dtype=np.int64)
    pairs = np.unique(np.column_stack([scan, table.sensor]), axis=0)
    np.add.at(sensors_per_scan, pairs[:, 0], 1)
    if len(np.unique(table.sensor)) >= 2 and n_scans and sensors_per_scan.max() < 2:
        raise ValueError(
            f"MEAS: rows grouped by exact time give {n_scans} scan(s), none with reports of two sensors, so "
            "nothing can be associated: are the clocks jittered? Group reports close in time with "
            "--scan-window SECONDS (or name a scan column with --scan-column)"
        )


def main(args: argparse.Namespace) -> int:
    files = plan_outputs(args, {"MEAS": args.measurements, "SENS": args.sensors})
    table, sensors = read_inputs(args)
    window = args.scan_window
    keys, scan = scan_keys(table, args.scan_column, name="--scan-column", window=window)
    if args.scan_column == "time" and window is None:
        check_scans_have_two_sensors(table, scan, len(keys))
    order, offsets = scan_rows(scan, len(keys))
    groups = [order[offsets[k] : offsets[k + 1]] for k in range(len(keys))]
    associator = StaticAssociator(**given_parameters(args, args.parameter_names))
    if args.scan_column != "time":  # the user named the scans: their times may differ
        warnings.filterwarnings("ignore", message=r"measurements: \d+ distinct times")
    target = np.full(len(table), -1, dtype=np.int64)
    targets: list[dict[str, Any]] = []
    outcomes: list[dict[str, Any]] = []
    for k, rows in enumerate(tqdm(groups, desc="associate", unit="scan", file=sys.stderr, disable=None, leave=False)):
        found = associator.associate(table.select(rows), sensors)
        outcomes.append(
            {"scan": k, "termination": found.termination, "success": found.success, "message": found.message}
        )
        for t in range(len(found.positions)):
            used = found.rows[t] >= 0
            targets.append(
                {
                    "target": len(targets),
                    "scan": k,
                    "position": found.positions[t],
                    "covariance": found.covariances[t],
                    "cost": found.costs[t],
                    "rows": rows[found.rows[t][used]],
                }
            )
        inside = found.labels >= 0
        target[rows[inside]] = found.labels[inside] + (len(targets) - len(found.positions))
    false_alarms = int(np.sum(target < 0))
    write_outputs(
        args,
        files,
        row_columns(table, target, label_name="target", scan=scan),
        with_geodetic(
            {
                "method": associator.method,
                "success": all(o["success"] for o in outcomes),
                "scans": len(groups),
                "scan_outcomes": outcomes,
                "targets": targets,
            },
            "targets",
            sensors,
            np.array([t["position"] for t in targets]).reshape(-1, sensors.ndim),
        ),
        f"{len(groups)} scan(s), {len(targets)} target(s), {false_alarms} of {len(table)} reports false alarms",
    )
    if args.plot:
        from ..plots_data import plot_association

        write_atomically(args.plot, lambda p: plot_association(table, sensors, target, targets, p))
    return 0
